// Paper Table 1: immersion algorithm statistics per model — input vertices, triangles and genus;
// cells, patches, arcs and the largest winding number of the cell complex; output tets; wall
// times of the cell complex (t-cell), the immersion search (t-imm), the meshing (t-mesh) and
// all three (t-total). Our models are the generated analogues of the paper's (dim3/generators3.h:
// head, helix, quintuple torus, tree, Sacht small and large) meshed on a generated grid, and the
// paper's own quintuple torus (../shared/data/real/3d/quintupleTorus.obj) meshed on its Vega
// background (tet/quintupleTorus.veg), skipped when the data is absent.
// Checks: the counts the generators derive by hand (tests/support/expected_surface_counts.h), the real
// quintuple torus's counts from the paper (314 cells, 886 patches, 850 arcs, max winding 7, output
// tets within 0.1% of the paper's 84,905),
// every output tet count against the mesh (and, for the smallest model, against its .mesh file
// read back), and t-total >= t-cell + t-imm + t-mesh. Writes table1.md (each of our rows beside
// the paper's, labelled "paper") and table1.csv.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <map>
#include <optional>
#include <set>

#include "core/union_find.h"
#include "dim3/generators3.h"
#include "dim3/mesh3.h"
#include "dim3/self_connecting.h"
#include "dim3/surface.h"
#include "dim3/tet_mesh.h"
#include "figures/figure_common.h"
#include "render/mesh_scenes.h"
#include "tests/support/expected_surface_counts.h"

using namespace imm;

namespace {

/// One row of the paper's Table 1, as printed.
struct PaperRow {
  std::string model, vertices, triangles, genus, cells, patches, arcs, max_winding, tets, t_cell, t_imm,
      t_mesh, t_total;
};

const std::vector<PaperRow>& paper_rows() {
  static const std::vector<PaperRow> rows = {
      {"head", "3,020", "6,036", "0", "3", "3", "2", "2", "566,515", "0.34", "0.0090", "38.0", "38.4"},
      {"helix", "100,020", "200,036", "0", "3", "3", "2", "2", "36,182", "56.4", "0.0003", "190", "246"},
      {"yeahright-on-ground", "94,063", "188,646", "131", "117", "263", "362", "4", "83,024", "14.2", "0.12",
       "57.1", "71.4"},
      {"quintuple torus", "15,211", "30,438", "5", "314", "886", "1,700", "7", "84,905", "11.6", "4.89", "35.9",
       "52.4"},
      {"tree", "163,998", "328,152", "40", "131", "259", "258", "2", "32,457", "15.9", "0.19", "130", "146"},
      {"Sacht (small)", "12,448", "24,896", "1", "26", "49", "48", "2", "112,554", "2.77", "0.0015", "19.7",
       "22.5"},
      {"Sacht (large)", "24,160", "48,320", "1", "41", "79", "78", "2", "225,338", "6.01", "0.0045", "42.2",
       "48.2"},
  };
  return rows;
}

struct Row {
  std::string model;  ///< our model, with its generator call or file
  std::string paper;  ///< the paper's model name it stands beside
  std::string background;
  std::size_t vertices = 0, triangles = 0;
  long genus = 0;
  std::size_t cells = 0, patches = 0, arcs = 0;
  int max_winding = 0;
  std::size_t helper_boxes = 0;
  std::size_t output_tets = 0;
  double t_cell = 0, t_imm = 0, t_mesh = 0, t_total = 0;
  dim3::TetMesh mesh;  ///< kept to write the smallest one
  dim3::Surface surface;       ///< the input, for its picture
  std::vector<bool> crossing;  ///< per input triangle: intersects another (red in the picture)
};

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// Total genus of a closed surface: per connected component V - E + F = 2 - 2g, summed.
long surface_genus(const dim3::Surface& s) {
  UnionFind uf(s.vertex_count());
  for (const dim3::Triangle& t : s.triangles) {
    uf.unite(t[0], t[1]);
    uf.unite(t[0], t[2]);
  }
  std::map<std::uint32_t, long> chi;  // V - E + F per component (by root vertex)
  std::vector<bool> used(s.vertex_count(), false);
  for (const dim3::Triangle& t : s.triangles)
    for (std::uint32_t v : t) used[v] = true;
  for (std::uint32_t v = 0; v < s.vertex_count(); ++v)
    if (used[v]) ++chi[uf.find(v)];  // + V
  std::set<std::pair<std::uint32_t, std::uint32_t>> edges;
  for (const dim3::Triangle& t : s.triangles) {
    ++chi[uf.find(t[0])];  // + F
    for (int k = 0; k < 3; ++k) edges.emplace(std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3]));
  }
  for (const auto& [a, b] : edges) --chi[uf.find(a)];  // - E
  long genus = 0;
  for (const auto& [root, c] : chi) {
    figures::expect(c <= 2 && (2 - c) % 2 == 0, "Euler characteristic " + std::to_string(c) +
                                                     " of a closed orientable component");
    genus += (2 - c) / 2;
  }
  return genus;
}

Row run(const std::string& model, const std::string& paper, const dim3::Surface& surface,
        const dim3::MeshOptions& options) {
  std::cout << "table_1: " << model << ": " << surface.vertex_count() << " vertices, " << surface.triangle_count()
            << " triangles ..." << std::endl;
  Row r;
  r.model = model;
  r.paper = paper;
  r.background = options.background_path ? std::filesystem::path(*options.background_path).filename().string()
                                         : "grid " + std::to_string(options.resolution);
  r.vertices = surface.vertex_count();
  r.triangles = surface.triangle_count();
  r.genus = surface_genus(surface);

  dim3::ImmerseOptions immerse;
  immerse.build.exact_volumes = false;  // the search does not read volumes (BENCHMARKS: doubles)
  const auto start = std::chrono::steady_clock::now();
  const dim3::Immersed im = dim3::immerse_surface(surface, immerse);
  figures::expect(im.build.complex && im.search.status == ImmersionStatus::Immersible &&
                      !im.search.immersions.empty(),
                  model + " is immersible" + (im.build.report.ok() ? "" : ": " + im.build.report.summary()));
  const auto mesh_start = std::chrono::steady_clock::now();
  dim3::MeshResult mesh = dim3::mesh_immersion(*im.build.complex, im.search.immersions.front(), options,
                                                 im.input_vertices, im.input_triangles);
  r.t_mesh = seconds_since(mesh_start);
  r.t_total = seconds_since(start);
  figures::expect(mesh.report.ok(), model + " meshes: " + mesh.report.summary());

  const CellComplex<3>& c = im.build.complex->complex;
  r.cells = c.cell_count();
  r.patches = c.patch_count();
  r.arcs = c.arc_count();
  r.max_winding = c.max_winding_number();
  r.helper_boxes = im.helper_boxes.size();
  r.output_tets = mesh.stats.output_tets;
  r.t_cell = im.build_seconds;
  r.t_imm = im.search_seconds;
  r.mesh = std::move(mesh.mesh);
  r.surface = surface;
  r.crossing = render::intersecting_triangles(*im.build.complex);
  r.crossing.resize(surface.triangle_count());  // the user's triangles (helper boxes come after)

  figures::expect(r.cells >= 1 && r.patches >= 1 && r.max_winding >= 1, model + ": a non-empty complex");
  figures::expect(r.output_tets == r.mesh.tets.size() && r.output_tets > 0,
                  model + ": stats.output_tets equals the output mesh's tets");
  figures::expect(r.t_cell >= 0 && r.t_imm >= 0 && r.t_mesh >= 0 &&
                      r.t_total >= r.t_cell + r.t_imm + r.t_mesh - 1e-3,
                  model + ": t-total >= t-cell + t-imm + t-mesh");
  std::cout << "table_1: " << model << ": " << r.cells << " cells, " << r.patches << " patches, " << r.arcs
            << " arcs, max winding " << r.max_winding << ", " << r.output_tets << " tets; t-cell " << r.t_cell
            << " s, t-imm " << r.t_imm << " s, t-mesh " << r.t_mesh << " s, t-total " << r.t_total << " s"
            << std::endl;
  return r;
}

/// A generated model, checked against the counts its construction implies.
/// `genus`: the total genus the construction gives (sphere-like pieces 0, each torus 1).
Row run_generated(const std::string& generator, const std::vector<std::string>& params, long genus,
                  const std::string& paper, const dim3::MeshOptions& options) {
  const dim3::SurfaceGenerateResult g = dim3::generate_surface(generator, params);
  figures::expect(g.ok(), generator + ": " + g.error);
  std::string model = generator;
  for (const std::string& p : params) model += " " + p;
  Row r = run(model, paper, g.surface, options);
  const test_support::ExpectedSurfaceCounts e = test_support::expected_surface_counts(generator, params);
  figures::expect(e.error.empty(), e.error);
  figures::expect(r.genus == genus, model + ": genus " + std::to_string(r.genus) + ", the construction gives " +
                                        std::to_string(genus));
  const auto same = [&](long expected, std::size_t got, const std::string& what) {
    figures::expect(expected < 0 || static_cast<std::size_t>(expected) == got,
                    model + ": " + what + " " + std::to_string(got) + ", the construction gives " +
                        std::to_string(expected));
  };
  same(e.cells, r.cells, "cells");
  same(e.patches, r.patches, "patches");
  same(e.arcs, r.arcs, "arcs");
  figures::expect(e.max_winding < 0 || e.max_winding == r.max_winding,
                  model + ": max winding " + std::to_string(r.max_winding));
  return r;
}

std::string thousands(std::size_t n) {
  const std::string digits = std::to_string(n);
  std::string s;
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) s += ',';
    s += digits[i];
  }
  return s;
}

/// Seconds with three significant digits, like the paper ("0.34", "0.0090", "246").
std::string seconds(double s) {
  std::ostringstream o;
  if (s >= 100) {
    o << std::fixed << std::setprecision(0) << s;
  } else if (s > 0) {
    int decimals = s >= 10 ? 1 : 2;
    for (double x = s; x < 1 && decimals < 6; x *= 10) ++decimals;
    o << std::fixed << std::setprecision(decimals) << s;
  } else {
    o << "0";
  }
  return o.str();
}

}  // namespace

int main(int argc, char** argv) {
  return figures::main_guard([&] {
    const auto args = figures::parse_args(argc, argv, "table_1");
    figures::describe("Table 1 (models of Figs. 1-3, 22, 24)",
                      "per model: vertices, triangles, genus, cells, patches, arcs, max winding, output tets "
                      "and times; the models' collided faces are red in their pictures.");
    const bool q = args.quick;
    dim3::MeshOptions grid;
    grid.resolution = q ? 8 : 24;

    std::vector<Row> rows;
    rows.push_back(run_generated("head", {q ? "16" : "44"}, 0, "head", grid));
    rows.push_back(run_generated("helix", {q ? "4" : "100", q ? "12" : "20"}, 0, "helix", grid));
    rows.push_back(run_generated("quintuple-torus", {q ? "8" : "54"}, 5, "quintuple torus", grid));

    const std::filesystem::path obj = std::filesystem::path(IMM_SHARED_DATA_DIR) / "3d" / "quintupleTorus.obj";
    const std::filesystem::path veg = std::filesystem::path(IMM_SHARED_DATA_DIR) / "tet" / "quintupleTorus.veg";
    bool real = false;
    if (std::filesystem::exists(obj) && std::filesystem::exists(veg)) {
      const dim3::SurfaceReadResult read = dim3::read_surface(obj.string());
      figures::expect(read.report.ok(), "quintupleTorus.obj reads: " + read.report.summary());
      dim3::MeshOptions vega;
      vega.background_path = veg.string();
      Row r = run("quintupleTorus.obj", "quintuple torus", read.surface, vega);
      // The paper's own input: its size is the paper's; the counts are those this code is known to give.
      figures::expect(r.vertices == 15211 && r.triangles == 30438 && r.genus == 5,
                      "quintupleTorus.obj: 15,211 vertices, 30,438 triangles, genus 5 (the paper's)");
      figures::expect(r.cells == 314 && r.patches == 886 && r.arcs == 850 && r.max_winding == 7,
                      "quintupleTorus.obj: 314 cells, 886 patches, 850 arcs, max winding 7");
      // The paper's 84,903-84,905 output tets; our cutting of the background tets may differ from
      // the reference implementation's in a few of them (the exact count is a regression snapshot
      // of tests/dim3/mesh3_test.cpp, not checked here): within 0.1%.
      constexpr std::size_t kPaperTets = 84905;
      figures::expect(r.output_tets * 1000 >= kPaperTets * 999 && r.output_tets * 1000 <= kPaperTets * 1001,
                      "quintupleTorus.obj on quintupleTorus.veg: within 0.1% of the paper's 84,905 output tets, got " +
                          std::to_string(r.output_tets));
      rows.push_back(std::move(r));
      real = true;
    } else {
      std::cout << "table_1: " << obj.string() << " or " << veg.string() << " absent: row skipped" << std::endl;
    }

    rows.push_back(run_generated("tree", {q ? "40" : "2734"}, 0, "tree", grid));
    rows.push_back(run_generated("sacht-torus", {q ? "24" : "146", "0"}, 1, "Sacht (small)", grid));
    rows.push_back(run_generated("sacht-torus", {q ? "24" : "188", "1"}, 1, "Sacht (large)", grid));

    // The smallest output as a Medit file, read back: the tet count survives the file.
    const auto smallest = std::min_element(rows.begin(), rows.end(), [](const Row& a, const Row& b) {
      return a.output_tets < b.output_tets;
    });
    std::string stem = smallest->model;
    std::replace_if(stem.begin(), stem.end(), [](char ch) { return !std::isalnum(static_cast<unsigned char>(ch)); }, '_');
    const std::string mesh_file = "table1_" + stem + ".mesh";
    figures::write(args, mesh_file, dim3::format_medit_3d(smallest->mesh));
    const dim3::TetReadResult back = dim3::read_tet_mesh(args.out + "/" + mesh_file);
    figures::expect(back.report.ok() && back.reoriented == 0, mesh_file + " reads back: " + back.report.summary());
    figures::expect(back.mesh.tets.size() == smallest->output_tets,
                    mesh_file + ": " + std::to_string(back.mesh.tets.size()) + " tets in the file, the table says " +
                        std::to_string(smallest->output_tets));

    // Pictures: every model with its intersecting triangles red; the smallest output's tets by
    // graph node, pulled apart.
    for (const Row& r : rows) {
      std::string file = r.paper;
      std::replace_if(file.begin(), file.end(), [](char ch) { return !std::isalnum(static_cast<unsigned char>(ch)); }, '_');
      if (r.model.find(".obj") != std::string::npos) file += "_obj";
      const std::size_t red = static_cast<std::size_t>(std::count(r.crossing.begin(), r.crossing.end(), true));
      render::Scene scene;
      scene.parts.push_back(render::surface_part(r.surface, r.crossing, render::colors::kSurface, true));
      scene.view = render::View{30, 30, 2};
      if (const auto image = figures::picture(args, scene, "table1_" + file + ".png",
                                              r.model + " (" + std::to_string(red) + " intersecting triangles red)"))
        figures::expect((figures::hue_pixels(*image, render::colors::kIntersecting) > 0) == (red > 0),
                        r.model + ": red pixels in its picture exactly when it has intersecting triangles");
    }
    {
      render::TetStyle style;
      style.explode = 0.25;
      style.edges = !q;
      render::Scene scene = render::tet_mesh_scene(smallest->mesh, style);
      scene.view = render::View{30, 30, 2};
      figures::picture(args, scene, "table1_" + stem + "_tets.png", smallest->model + ": output tets by graph node");
    }

    std::ostringstream md, csv;
    md << "# Table 1: immersion algorithm statistics" << (q ? " (--quick sizes)" : "") << "\n\n"
       << "Each of our rows (`ours`) stands above the paper's row for the same model (**paper**).\n"
       << "Times are wall seconds (std::chrono::steady_clock) on this machine (2 cores); t-total runs\n"
       << "from the start of the cell complex to the end of meshing (input generation or reading\n"
       << "excluded). Generated models are meshed on a generated grid of " << grid.resolution
       << " cubes along the\n"
       << "longest side of the input's box; the paper's quintuple torus on its Vega background.\n\n"
       << "| model | source | background | vertices | triangles | genus | cells | patches | arcs | max winding # "
          "| output tets | t-cell | t-imm | t-mesh | t-total |\n"
       << "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    csv << "source,model,background,vertices,triangles,genus,cells,patches,arcs,max_winding,output_tets,"
           "t_cell,t_imm,t_mesh,t_total\n";
    const auto paper_line = [&](const PaperRow& p) {
      md << "| " << p.model << " | **paper** | | " << p.vertices << " | " << p.triangles << " | " << p.genus << " | "
         << p.cells << " | " << p.patches << " | " << p.arcs << " | " << p.max_winding << " | " << p.tets << " | "
         << p.t_cell << " | " << p.t_imm << " | " << p.t_mesh << " | " << p.t_total << " |\n";
      const auto plain = [](std::string s) {
        s.erase(std::remove(s.begin(), s.end(), ','), s.end());
        return s;
      };
      csv << "paper," << p.model << ",," << plain(p.vertices) << "," << plain(p.triangles) << "," << p.genus << ","
          << plain(p.cells) << "," << plain(p.patches) << "," << plain(p.arcs) << "," << p.max_winding << ","
          << plain(p.tets) << "," << p.t_cell << "," << p.t_imm << "," << p.t_mesh << "," << p.t_total << "\n";
    };
    for (const PaperRow& p : paper_rows()) {
      for (const Row& r : rows) {
        if (r.paper != p.model) continue;
        md << "| `" << r.model << "` | ours | " << r.background << " | " << thousands(r.vertices) << " | "
           << thousands(r.triangles) << " | " << r.genus << " | " << thousands(r.cells) << " | "
           << thousands(r.patches) << " | " << thousands(r.arcs) << " | " << r.max_winding << " | "
           << thousands(r.output_tets) << " | " << seconds(r.t_cell) << " | " << seconds(r.t_imm) << " | "
           << seconds(r.t_mesh) << " | " << seconds(r.t_total) << " |\n";
        csv << "ours," << r.model << "," << r.background << "," << r.vertices << "," << r.triangles << ","
            << r.genus << "," << r.cells << "," << r.patches << "," << r.arcs << "," << r.max_winding << ","
            << r.output_tets << "," << std::setprecision(6) << std::fixed << r.t_cell << "," << r.t_imm << ","
            << r.t_mesh << "," << r.t_total << std::defaultfloat << "\n";
      }
      paper_line(p);
    }
    double total = 0;
    std::size_t boxes = 0;
    for (const Row& r : rows) {
      total += r.t_total;
      boxes += r.helper_boxes;
    }
    md << "\nNotes.\n\n"
       << "- Conventions: our `cells` are the regions of non-zero winding number and our `arcs` are\n"
       << "  geometric intersection curves, each counted once. The paper counts every arc once per\n"
       << "  sheet (its quintuple torus: 1,700 = 2 x 850), and its head and helix rows count 3 cells\n"
       << "  where ours have 2 (with the outside region, 3 regions).\n"
       << "- Genus is the input's, from V - E + F = 2 - 2g per connected component, summed. The\n"
       << "  generated tree is a union of capped cylinders (genus 0 each), the generated quintuple\n"
       << "  torus five separate tori plus cylinders (genus 5), the Sacht tori one torus plus columns.\n"
       << "- The generated models are analogues, not the paper's meshes: sizes are chosen near the\n"
       << "  paper's triangle counts" << (q ? " in full mode (this is the --quick run)" : "") << ".\n"
       << "  Their complexes differ (e.g. each of the tree's branches pierces its parent once), so\n"
       << "  cells, patches and arcs are not expected to match the paper's; they match the counts\n"
       << "  each construction gives (dim3/generators3.h), which the program checks.\n"
       << (real ? "- `quintupleTorus.obj` is the paper's input on the paper's background mesh.\n"
                : "- `quintupleTorus.obj` (../shared/data) is absent here: its row is skipped.\n")
       << "- yeahright-on-ground: no input here (paper row only).\n"
       << "- Helper boxes added: " << boxes << ". Exact region volumes are off (the search does not read them).\n"
       << "- The smallest output is written as `" << mesh_file << "` (" << thousands(smallest->output_tets)
       << " tets, read back).\n"
       << "- Sum of t-total over our rows: " << seconds(total) << " s.\n";
    figures::write(args, "table1.md", md.str());
    figures::write(args, "table1.csv", csv.str());
  });
}
