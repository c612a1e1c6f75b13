// The Python module `immersion` (pybind11, numpy): the public C++ API (api/immersion/immersion.h)
// with numpy arrays in and out. Thin: it checks array shapes and dtypes, converts, releases the
// GIL around the call, and maps immersion::Error to Python exceptions carrying the same message,
// `kind` and `exit_code`. No algorithm here.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <string>

#include "immersion/immersion.h"

namespace py = pybind11;
using immersion::Error;
using immersion::ErrorKind;

namespace {

/// The exception classes, created at import (see PYBIND11_MODULE).
py::object error_class, invalid_input_class, not_immersible_class, internal_class;

[[noreturn]] void invalid(const std::string& message) { throw Error(ErrorKind::InvalidInput, message); }

std::string shape_of(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t k = 0; k < a.ndim(); ++k) s += (k ? ", " : "") + std::to_string(a.shape(k));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

/// An n x cols float64 array (any real dtype is converted), C order.
py::array_t<double, py::array::c_style> real_matrix(const py::handle& object, py::ssize_t cols,
                                                    const std::string& what) {
  py::array a = py::array::ensure(object);
  if (!a) invalid(what + " must be an array of shape (n, " + std::to_string(cols) + ")");
  const char kind = a.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u')
    invalid(what + " must hold real numbers, got dtype " + std::string(py::str(a.dtype())));
  if (a.ndim() != 2 || a.shape(1) != cols)
    invalid(what + " must have shape (n, " + std::to_string(cols) + "), got " + shape_of(a));
  return py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
}

/// An m x 3 integer array (no float: 1.5 is not an index).
py::array_t<long long, py::array::c_style> index_matrix(const py::handle& object, const std::string& what) {
  py::array a = py::array::ensure(object);
  if (!a) invalid(what + " must be an integer array of shape (m, 3)");
  const char kind = a.dtype().kind();
  if (kind != 'i' && kind != 'u')
    invalid(what + " must hold integers, got dtype " + std::string(py::str(a.dtype())));
  if (a.ndim() != 2 || a.shape(1) != 3) invalid(what + " must have shape (m, 3), got " + shape_of(a));
  return py::array_t<long long, py::array::c_style | py::array::forcecast>::ensure(a);
}

immersion::Surface make_surface(const py::handle& V, const py::handle& F, const std::string& name) {
  const auto v = real_matrix(V, 3, "V");
  const auto f = index_matrix(F, "F");
  // Unsigned indices past 2^63 wrap to negatives in the cast above: read them as they were.
  py::array raw = py::array::ensure(F);
  const bool is_unsigned = raw.dtype().kind() == 'u';
  using Unsigned = py::array_t<unsigned long long, py::array::c_style | py::array::forcecast>;
  const Unsigned unsigned_f = is_unsigned ? Unsigned::ensure(raw) : Unsigned();
  immersion::Surface s;
  s.name = name;
  s.vertices.resize(static_cast<std::size_t>(v.shape(0)));
  std::memcpy(s.vertices.data(), v.data(), s.vertices.size() * sizeof(s.vertices[0]));
  s.triangles.reserve(static_cast<std::size_t>(f.shape(0)));
  const auto fa = f.unchecked<2>();
  for (py::ssize_t t = 0; t < f.shape(0); ++t) {
    std::array<int, 3> tri{};
    for (int k = 0; k < 3; ++k) {
      const long long i = fa(t, k);
      // Out of range indices are the library's defect (named with the triangle); an index that
      // does not fit an int is named here, as given (it was reported as vertex -1).
      if (i < std::numeric_limits<int>::min() || i > std::numeric_limits<int>::max() || (is_unsigned && i < 0)) {
        const std::string index =
            is_unsigned ? std::to_string(unsigned_f.template unchecked<2>()(t, k)) : std::to_string(i);
        invalid("F: triangle " + std::to_string(t) + " refers to vertex " + index + ", but there are " +
                std::to_string(v.shape(0)) + " vertices");
      }
      tri[k] = static_cast<int>(i);
    }
    s.triangles.push_back(tri);
  }
  return s;
}

immersion::Curves make_curves(const py::list& curves, const std::string& name) {
  immersion::Curves c;
  c.name = name;
  for (std::size_t k = 0; k < curves.size(); ++k) {
    const auto a = real_matrix(curves[k], 2, "curve " + std::to_string(k));
    auto& curve = c.curves.emplace_back(static_cast<std::size_t>(a.shape(0)));
    std::memcpy(curve.data(), a.data(), curve.size() * sizeof(curve[0]));
  }
  return c;
}

template <class T, std::size_t N>
py::array_t<T> to_array(const std::vector<std::array<T, N>>& rows) {
  py::array_t<T> a({static_cast<py::ssize_t>(rows.size()), static_cast<py::ssize_t>(N)});
  if (!rows.empty()) std::memcpy(a.mutable_data(), rows.data(), rows.size() * sizeof(rows[0]));
  return a;
}

template <class T>
py::array_t<T> to_array(const std::vector<T>& values) {
  py::array_t<T> a(static_cast<py::ssize_t>(values.size()));
  if (!values.empty()) std::memcpy(a.mutable_data(), values.data(), values.size() * sizeof(T));
  return a;
}

immersion::SearchOptions search_options(std::size_t max, std::size_t max_states, double time_limit,
                                        bool helper_boxes, unsigned threads,
                                        std::optional<double> repair_folds = std::nullopt) {
  if (repair_folds && !(*repair_folds > 0 && std::isfinite(*repair_folds)))
    invalid("repair_folds must be a positive number");
  immersion::SearchOptions o;
  o.repair_folds = repair_folds;
  o.max_immersions = max;
  o.max_states = max_states;
  o.time_limit_seconds = time_limit;
  o.helper_boxes = helper_boxes;
  o.threads = threads;
  return o;
}

/// mesh_immersion's keywords, the same for curves and surfaces (the library refuses the 3D-only
/// ones for curves).
template <int D>
immersion::SimplexMesh<D> mesh_immersion_with(const immersion::Immersions<D>& found, std::size_t k,
                                              std::optional<int> resolution, std::optional<std::string> background,
                                              const std::string& method, unsigned threads, bool conforming,
                                              std::optional<double> edge_length, double radius_edge,
                                              double min_dihedral, std::optional<int> surface_resolution,
                                              std::optional<int> gap_resolution) {
  // A usage error, as `immerse mesh --resolution N --background FILE` (exit 64): a plain
  // ValueError, not InvalidInput (the input is not at fault).
  if (resolution && background) throw py::value_error("resolution and background exclude each other");
  immersion::MeshOptions o;
  o.immersion = k;
  o.resolution = resolution;
  o.background = std::move(background);
  o.conforming = conforming;
  if (method == "csg") {
    o.method = immersion::MeshMethod::Csg;
  } else if (method != "clip") {
    invalid("method must be 'clip' or 'csg', got '" + method + "'");
  }
  o.threads = threads;
  o.edge_length = edge_length;
  o.radius_edge = radius_edge;
  o.min_dihedral = min_dihedral;
  o.surface_resolution = surface_resolution;
  o.gap_resolution = gap_resolution;
  return immersion::mesh_immersion(found, o);
}

py::dict graph_dict(const immersion::ImmersionGraph& g) {
  py::dict d;
  d["node_cell"] = to_array(g.node_cell);
  d["edges"] = to_array(g.edges);
  d["patch_owner"] = to_array(g.patch_owner);
  d["components"] = g.components;
  return d;
}

template <int D>
void bind_dimension(py::module_& m) {
  const std::string suffix = std::to_string(D);
  using Complex = immersion::Complex<D>;
  py::class_<Complex>(m, ("Complex" + suffix).c_str(),
                      "The exact cell complex (paper §4): counts, windings, areas/volumes.")
      .def_property_readonly("dimension", [](const Complex&) { return D; })
      .def_property_readonly("regions", &Complex::region_count)
      .def_property_readonly("cells", &Complex::cell_count)
      .def_property_readonly("patches", &Complex::patch_count)
      .def_property_readonly("arcs", &Complex::arc_count)
      .def_property_readonly("max_winding", &Complex::max_winding_number)
      .def_property_readonly("windings", [](const Complex& c) { return to_array(c.cell_winding_numbers()); },
                             "winding number per cell")
      .def_property_readonly("volumes", [](const Complex& c) { return to_array(c.cell_measures()); },
                             "area (2D) or volume (3D) per cell, rounded from the exact value")
      .def_property_readonly("volumes_exact", &Complex::cell_measures_exact,
                             "exact area/volume per cell as 'p/q' ('' when not exact)")
      .def_property_readonly("cell_regions", [](const Complex& c) { return to_array(c.cell_regions()); })
      .def_property_readonly("patch_regions", [](const Complex& c) { return to_array(c.patch_regions()); },
                             "per patch: (positive-side region, negative-side region)")
      .def_property_readonly("reversed", &Complex::reversed)
      .def("__repr__", [](const Complex& c) {
        return "<immersion.Complex" + std::to_string(D) + ": " + std::to_string(c.cell_count()) + " cells, " +
               std::to_string(c.patch_count()) + " patches, " + std::to_string(c.arc_count()) + " arcs>";
      });

  using Immersions = immersion::Immersions<D>;
  py::class_<Immersions>(m, ("Immersions" + suffix).c_str(),
                         "The immersions found (graphs of cell copies) and the complex they refer to.")
      .def_property_readonly("graphs",
                             [](const Immersions& s) {
                               py::list l;
                               for (const auto& g : s.graphs) l.append(graph_dict(g));
                               return l;
                             },
                             "per immersion: node_cell, edges (inner, outer, patch), patch_owner, components")
      .def_readonly("complete", &Immersions::complete)
      .def_readonly("complex", &Immersions::complex)
      .def_readonly("helper_boxes", &Immersions::helper_boxes)
      .def_readonly("notes", &Immersions::notes)
      .def("__len__", [](const Immersions& s) { return s.graphs.size(); });

  using Mesh = immersion::SimplexMesh<D>;
  py::class_<Mesh>(m, ("Mesh" + suffix).c_str(), "An unglued simplex mesh with the embedding of the input.")
      .def_property_readonly("V", [](const Mesh& s) { return to_array(s.vertices); }, "vertices, (n, D) float64")
      .def_property_readonly("T", [](const Mesh& s) { return to_array(s.elements); },
                             "elements, (m, D + 1) int32, positively oriented")
      .def_property_readonly("node", [](const Mesh& s) { return to_array(s.node); }, "graph node per element")
      .def_property_readonly("embedding_element", [](const Mesh& s) { return to_array(s.embedding_element); },
                             "per input vertex: the element holding it")
      .def_property_readonly("embedding_weights", [](const Mesh& s) { return to_array(s.embedding_weights); },
                             "per input vertex: D + 1 barycentric weights in its element")
      .def_property_readonly("input_shift", [](const Mesh& s) { return s.input_shift; })
      .def("write", [](const Mesh& s, const std::string& path) { immersion::write_mesh(s, path); },
           py::arg("path"),
           D == 2 ? "writes .mesh (Medit)" : "writes .mesh, .vtu, .veg, .msh (Gmsh 4.1) or .node (+ .ele)");
}

}  // namespace

PYBIND11_MODULE(immersion, m) {
  m.doc() =
      "Immersion of self-intersecting curves and surfaces (Li & Barbic 2018): exact cell complex, "
      "immersion search and unglued meshes, with numpy arrays.";
  m.attr("__version__") = immersion::version();

  // Exceptions: Error (kind, exit_code) and its three kinds; InvalidInput is also a ValueError.
  py::object exception = py::module_::import("builtins").attr("Exception");
  py::object value_error = py::module_::import("builtins").attr("ValueError");
  auto make = [&](const char* name, py::tuple bases, const char* doc) {
    py::object cls = py::reinterpret_steal<py::object>(
        PyErr_NewExceptionWithDoc((std::string("immersion.") + name).c_str(), doc, bases.ptr(), nullptr));
    m.attr(name) = cls;
    return cls;
  };
  error_class = make("Error", py::make_tuple(exception),
                     "An immersion failure: str() is the program's message; kind and exit_code as `immerse`.");
  invalid_input_class = make("InvalidInput", py::make_tuple(error_class, value_error),
                             "Defective input (exit code 2): every defect with ids and coordinates.");
  not_immersible_class = make("NotImmersible", py::make_tuple(error_class),
                              "Valid input without a (simple) immersion (exit code 3).");
  internal_class = make("InternalError", py::make_tuple(error_class), "A bug or an I/O failure (exit code 1).");
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const Error& e) {
      py::object cls = e.kind() == ErrorKind::InvalidInput    ? invalid_input_class
                       : e.kind() == ErrorKind::NotImmersible ? not_immersible_class
                                                              : internal_class;
      py::object error = cls(e.what());
      error.attr("kind") = e.kind() == ErrorKind::InvalidInput    ? "invalid-input"
                           : e.kind() == ErrorKind::NotImmersible ? "not-immersible"
                                                                  : "internal";
      error.attr("exit_code") = e.exit_code();
      PyErr_SetObject(cls.ptr(), error.ptr());
    }
  });

  py::class_<immersion::Surface>(m, "Surface", "A closed triangle mesh: V (n, 3) float64, F (m, 3) int.")
      .def(py::init([](const py::object& V, const py::object& F, const std::string& name) {
             return make_surface(V, F, name);
           }),
           py::arg("V"), py::arg("F"), py::arg("name") = "<arrays>")
      .def_property_readonly("V", [](const immersion::Surface& s) { return to_array(s.vertices); })
      .def_property_readonly("F", [](const immersion::Surface& s) { return to_array(s.triangles); })
      .def_readonly("name", &immersion::Surface::name);
  py::class_<immersion::Curves>(m, "Curves", "Closed 2D curves: a list of (n_i, 2) float64 arrays.")
      .def(py::init([](const py::list& curves, const std::string& name) { return make_curves(curves, name); }),
           py::arg("curves"), py::arg("name") = "<arrays>")
      .def_property_readonly("curves",
                             [](const immersion::Curves& c) {
                               py::list l;
                               for (const auto& curve : c.curves) l.append(to_array(curve));
                               return l;
                             })
      .def_readonly("name", &immersion::Curves::name);

  bind_dimension<2>(m);
  bind_dimension<3>(m);

  using py::arg;
  const auto release = py::call_guard<py::gil_scoped_release>();
  m.def("read_surface", &immersion::read_surface, arg("path"), release,
        "Reads OBJ, OFF, PLY or STL. Raises InvalidInput naming every defect.");
  m.def("read_curves", &immersion::read_curves, arg("path"), release,
        "Reads 2D curves (text, SVG, OBJ v/l). Raises InvalidInput naming every defect.");

  m.def(
      "build_complex",
      [](const immersion::Surface& s, bool exact_volumes, unsigned threads, std::optional<double> repair_folds) {
        immersion::BuildOptions o;
        o.exact_volumes = exact_volumes;
        o.threads = threads;
        o.repair_folds = search_options(1, 1, 0.0, true, 0, repair_folds).repair_folds;  // checked there
        return immersion::build_complex(s, o);
      },
      arg("surface"), arg("exact_volumes") = true, arg("threads") = 0, arg("repair_folds") = py::none(), release,
      "The exact cell complex of a surface (paper §4).");
  m.def(
      "build_complex", [](const immersion::Curves& c) { return immersion::build_complex(c); }, arg("curves"),
      release, "The exact cell complex of 2D curves (paper §4).");

  m.def(
      "find_immersions",
      [](const immersion::Surface& s, std::size_t max, std::size_t max_states, double time_limit,
         bool helper_boxes, unsigned threads, std::optional<double> repair_folds) {
        return immersion::find_immersions(
            s, search_options(max, max_states, time_limit, helper_boxes, threads, repair_folds));
      },
      arg("surface"), arg("max") = 1, arg("max_states") = immersion::SearchOptions{}.max_states,
      arg("time_limit") = 0.0, arg("helper_boxes") = true, arg("threads") = 0, arg("repair_folds") = py::none(),
      release,
      "Searches the immersions (max=0: all of them). Raises NotImmersible with the conflict.");
  m.def(
      "find_immersions",
      [](const immersion::Curves& c, std::size_t max, std::size_t max_states, double time_limit) {
        return immersion::find_immersions(c, search_options(max, max_states, time_limit, true, 0));
      },
      arg("curves"), arg("max") = 1, arg("max_states") = immersion::SearchOptions{}.max_states,
      arg("time_limit") = 0.0, release);

  // One keyword set for curves and surfaces: the 3D-only keywords given for curves get the
  // library's InvalidInput ("edge_length is for 3D surfaces only"), not pybind11's TypeError.
  const immersion::MeshOptions defaults;
  const auto def_mesh_immersion = [&](auto mesh, const char* doc) {
    m.def("mesh_immersion", mesh, arg("immersions"), arg("immersion") = 0, arg("resolution") = py::none(),
          arg("background") = py::none(), arg("method") = "clip", arg("threads") = 0, arg("conforming") = false,
          arg("edge_length") = py::none(), arg("radius_edge") = defaults.radius_edge,
          arg("min_dihedral") = defaults.min_dihedral, arg("surface_resolution") = py::none(),
          arg("gap_resolution") = py::none(), release, doc);
  };
  def_mesh_immersion(&mesh_immersion_with<3>, "Meshes one immersion (paper §7): a Mesh3 with V, T, node, embedding.");
  def_mesh_immersion(&mesh_immersion_with<2>, "Meshes one immersion of curves (paper §7): a Mesh2.");
}
