// The simulation formats of the tet mesh (dim3/tet_mesh.h): Gmsh .msh 4.1 and TetGen .node/.ele.
// Each written mesh is read back twice: by the project's own reader (read_tet_mesh, a round trip
// that must give the same vertices bit for bit, the same tets in the same vertex order and the
// same references) and by a reader written here from Gmsh's documented format (sections, entity
// blocks, strictly positive 1-based tags, element type 4 = 4-node tetrahedron, physical group =
// graph node + 1), so that a writer and reader sharing one misunderstanding cannot both pass.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "dim3/tet_mesh.h"

namespace imm::dim3 {
namespace {

std::string temp_path(const std::string& name) {
  const std::filesystem::path dir =
      std::filesystem::path(testing::TempDir()) / "imm_mesh_formats_test";
  std::filesystem::create_directories(dir);
  return (dir / name).string();
}

std::string write_temp(const std::string& name, const std::string& contents) {
  const std::string path = temp_path(name);
  std::ofstream(path, std::ios::binary) << contents;
  return path;
}

/// A Kuhn grid (positive tets) with coordinates that need 17 digits, an unused vertex, and
/// references 0..4 in an order that differs from the tet order (so grouping tets by entity
/// would reorder them if the element tags did not keep the output order).
TetMesh sample_mesh() {
  TetMesh mesh = make_grid_background({{0.1, -1.0 / 3, 1e-7}, {1.7, 2.0 / 3, 0.9}}, 2);
  mesh.vertices.push_back({0.1 + 0.2, -1e-300, 1.0 / 3});
  mesh.reference.clear();
  for (std::size_t t = 0; t < mesh.tets.size(); ++t)
    mesh.reference.push_back(static_cast<int>((t * 7) % 5));
  return mesh;
}

// ---- an independent reader of Gmsh 4.1 ASCII, from the format's documentation -------------------

struct GmshFile {
  std::string version;
  int file_type = -1;
  std::map<int, std::string> physical_names;  // dim-3 physical tag -> name
  std::map<int, std::vector<int>> volume_physicals;  // volume entity tag -> physical tags
  std::map<long, std::array<double, 3>> nodes;       // node tag -> coordinates
  struct Element {
    int entity;
    int type;
    std::vector<long> nodes;
  };
  std::map<long, Element> elements;  // element tag -> element
  std::vector<std::string> errors;
};

GmshFile parse_gmsh_independently(const std::string& text) {
  GmshFile f;
  std::istringstream in(text);
  std::string section;
  auto expect_end = [&](const std::string& name) {
    std::string end;
    in >> end;
    if (end != "$End" + name) f.errors.push_back("no $End" + name + ", found " + end);
  };
  while (in >> section) {
    if (section == "$MeshFormat") {
      int data_size = 0;
      in >> f.version >> f.file_type >> data_size;
      expect_end("MeshFormat");
    } else if (section == "$PhysicalNames") {
      int n = 0;
      in >> n;
      for (int i = 0; i < n; ++i) {
        int dim = 0, tag = 0;
        std::string name;
        in >> dim >> tag;
        std::getline(in >> std::ws, name);
        if (dim == 3) f.physical_names[tag] = name;
      }
      expect_end("PhysicalNames");
    } else if (section == "$Entities") {
      int counts[4];
      for (int& c : counts) in >> c;
      for (int dim = 0; dim < 4; ++dim) {
        for (int i = 0; i < counts[dim]; ++i) {
          int tag = 0, physical_count = 0;
          double box[6];
          in >> tag;
          for (int k = 0; k < (dim == 0 ? 3 : 6); ++k) in >> box[k];
          in >> physical_count;
          std::vector<int> physicals(physical_count);
          for (int& p : physicals) in >> p;
          if (dim > 0) {
            int bounding = 0;
            in >> bounding;
            for (int k = 0, b = 0; k < bounding; ++k) in >> b;
          }
          if (dim == 3) f.volume_physicals[tag] = physicals;
        }
      }
      expect_end("Entities");
    } else if (section == "$Nodes") {
      long blocks = 0, count = 0, min_tag = 0, max_tag = 0;
      in >> blocks >> count >> min_tag >> max_tag;
      for (long b = 0; b < blocks; ++b) {
        int dim = 0, entity = 0, parametric = 0;
        long n = 0;
        in >> dim >> entity >> parametric >> n;
        if (parametric != 0) f.errors.push_back("parametric nodes");
        std::vector<long> tags(n);
        for (long& t : tags) in >> t;
        for (long t : tags) {
          std::array<double, 3> p{};
          in >> p[0] >> p[1] >> p[2];
          if (!f.nodes.emplace(t, p).second) f.errors.push_back("node tag twice");
        }
      }
      if (static_cast<long>(f.nodes.size()) != count) f.errors.push_back("node count");
      if (!f.nodes.empty() && (f.nodes.begin()->first != min_tag || f.nodes.rbegin()->first != max_tag))
        f.errors.push_back("node tag range");
      expect_end("Nodes");
    } else if (section == "$Elements") {
      long blocks = 0, count = 0, min_tag = 0, max_tag = 0;
      in >> blocks >> count >> min_tag >> max_tag;
      for (long b = 0; b < blocks; ++b) {
        int dim = 0, entity = 0, type = 0;
        long n = 0;
        in >> dim >> entity >> type >> n;
        if (dim != 3) f.errors.push_back("element block of dimension " + std::to_string(dim));
        const int per_element = type == 4 ? 4 : 0;
        for (long e = 0; e < n; ++e) {
          long tag = 0;
          in >> tag;
          GmshFile::Element element{entity, type, std::vector<long>(per_element)};
          for (long& v : element.nodes) in >> v;
          if (!f.elements.emplace(tag, element).second) f.errors.push_back("element tag twice");
        }
      }
      if (static_cast<long>(f.elements.size()) != count) f.errors.push_back("element count");
      if (!f.elements.empty() &&
          (f.elements.begin()->first != min_tag || f.elements.rbegin()->first != max_tag))
        f.errors.push_back("element tag range");
      expect_end("Elements");
    } else {
      f.errors.push_back("unexpected section " + section);
      break;
    }
  }
  if (!in.eof()) f.errors.push_back("stream failed");
  return f;
}

// ---- Gmsh ----------------------------------------------------------------------------------------

TEST(Gmsh, FollowsTheDocumentedFormat) {
  const TetMesh mesh = sample_mesh();
  const GmshFile f = parse_gmsh_independently(format_gmsh(mesh));
  ASSERT_TRUE(f.errors.empty()) << f.errors.front();
  EXPECT_EQ(f.version, "4.1");
  EXPECT_EQ(f.file_type, 0);  // ASCII
  // Node tags 1..N in vertex order, coordinates exactly.
  ASSERT_EQ(f.nodes.size(), mesh.vertices.size());
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    ASSERT_TRUE(f.nodes.count(static_cast<long>(v + 1)));
    EXPECT_EQ(f.nodes.at(static_cast<long>(v + 1)), mesh.vertices[v]) << "node tag " << v + 1;
  }
  // Element tags 1..M in tet order, type 4, the same corners, physical group = reference + 1.
  ASSERT_EQ(f.elements.size(), mesh.tets.size());
  std::set<int> entities;
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    const auto it = f.elements.find(static_cast<long>(t + 1));
    ASSERT_NE(it, f.elements.end()) << "element tag " << t + 1;
    const GmshFile::Element& e = it->second;
    EXPECT_EQ(e.type, 4);
    ASSERT_EQ(e.nodes.size(), 4u);
    for (int k = 0; k < 4; ++k) EXPECT_EQ(e.nodes[k], mesh.tets[t][k] + 1);
    ASSERT_TRUE(f.volume_physicals.count(e.entity)) << "entity " << e.entity;
    EXPECT_GT(e.entity, 0);
    const std::vector<int>& physicals = f.volume_physicals.at(e.entity);
    ASSERT_EQ(physicals.size(), 1u);
    EXPECT_EQ(physicals[0], mesh.reference[t] + 1);
    EXPECT_EQ(f.physical_names.at(physicals[0]),
              "\"node " + std::to_string(mesh.reference[t]) + "\"");
    entities.insert(e.entity);
  }
  EXPECT_EQ(entities.size(), 5u);  // one volume per graph node
}

TEST(Gmsh, RoundTripsThroughTheProjectsReader) {
  const TetMesh mesh = sample_mesh();
  const TetReadResult r = read_tet_mesh(write_temp("round.msh", format_gmsh(mesh)));
  ASSERT_TRUE(r.report.ok()) << r.report.summary();
  EXPECT_EQ(r.mesh.vertices, mesh.vertices);
  EXPECT_EQ(r.mesh.tets, mesh.tets);
  EXPECT_EQ(r.mesh.reference, mesh.reference);
  EXPECT_EQ(r.reoriented, 0u);
}

TEST(Gmsh, NegativeReferenceHasNoPhysicalGroupAndReadsBackAsMinusOne) {
  TetMesh mesh = sample_mesh();
  mesh.reference[3] = -1;
  const GmshFile f = parse_gmsh_independently(format_gmsh(mesh));
  ASSERT_TRUE(f.errors.empty()) << f.errors.front();
  EXPECT_TRUE(f.volume_physicals.at(f.elements.at(4).entity).empty());
  const TetReadResult r = read_tet_mesh(write_temp("negative.msh", format_gmsh(mesh)));
  ASSERT_TRUE(r.report.ok()) << r.report.summary();
  EXPECT_EQ(r.mesh.reference, mesh.reference);
}

TEST(Gmsh, ReadsWhatGmshWritesOtherTypesTagsAndSections) {
  // As Gmsh writes a meshed box: points, lines and triangles beside the tets, node tags not in
  // file order, parametric nodes on a curve, $Comments, physical groups on a surface too.
  const std::string text =
      "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n"
      "$Comments\nanything $Nodes here\n$EndComments\n"
      "$PhysicalNames\n2\n2 5 \"skin\"\n3 8 \"solid\"\n$EndPhysicalNames\n"
      "$Entities\n1 0 1 1\n"
      "1 0 0 0 0\n"
      "1 0 0 0 1 1 0 1 5 0\n"
      "7 0 0 0 1 1 1 1 8 1 1\n"
      "$EndEntities\n"
      "$Nodes\n3 5 2 20\n"
      "0 1 0 1\n20\n0 0 0\n"
      "1 3 1 2\n4\n3\n1 0 0 0.5\n0 1 0 0.25\n"
      "3 7 0 2\n2\n9\n0 0 1\n1 1 1\n"
      "$EndNodes\n"
      "$Elements\n3 3 1 12\n"
      "0 1 15 1\n1 20\n"
      "2 1 2 1\n5 20 4 3\n"
      "3 7 4 1\n12 20 4 3 2\n"
      "$EndElements\n";
  const TetReadResult r = read_tet_mesh(write_temp("gmsh_style.msh", text));
  ASSERT_TRUE(r.report.ok()) << r.report.summary();
  // Vertices in node-tag order: 2, 3, 4, 9, 20.
  const std::vector<Point3> expected{{0, 0, 1}, {0, 1, 0}, {1, 0, 0}, {1, 1, 1}, {0, 0, 0}};
  EXPECT_EQ(r.mesh.vertices, expected);
  ASSERT_EQ(r.mesh.tets.size(), 1u);
  // Tags 20 4 3 2 -> indices 4 2 1 0; (0,0,0), (1,0,0), (0,1,0), (0,0,1) is positive.
  EXPECT_EQ(r.mesh.tets[0], (Tet{4, 2, 1, 0}));
  EXPECT_EQ(r.reoriented, 0u);
  EXPECT_EQ(r.mesh.reference, std::vector<int>{7});  // physical 8 -> reference 7
}

TEST(Gmsh, RefusesWhatItCannotReadNamingFileAndLine) {
  const std::string header = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n";
  const std::vector<std::pair<std::string, std::string>> cases{
      {"$MeshFormat\n2.2 0 8\n$EndMeshFormat\n", "version '2.2'"},
      {"$MeshFormat\n4.1 1 8\n$EndMeshFormat\n", "binary"},
      {"$Nodes\n0 0 0 0\n$EndNodes\n", "'$MeshFormat' first"},
      {header + "$Nodes\n1 2 1 2\n3 1 0 2\n1\n2\n0 0 0\n", "the file ends"},
      {header + "$Nodes\n1 1 1 1\n3 1 0 1\n1\n0 0 x\n$EndNodes\n", ".msh:8: expected the coordinates"},
      {header + "$Nodes\n1 1 1 1\n3 1 0 1\n1\n0 0 0\n$EndNodes\n", "no '$Elements'"},
      {header + "$Nodes\n1 1 1 1\n3 1 0 1\n1\n0 0 0\n$EndNodes\n$Elements\n1 1 1 1\n3 1 4 1\n1 1 1 1 9\n$EndElements\n",
       "node tag 9"},
      {header + "$PartitionedEntities\n", "partitioned"},
      {header + "$Nodes\n1 2 1 2\n3 1 0 2\n1\n1\n0 0 0\n1 1 1\n$EndNodes\n$Elements\n0 0 0 0\n$EndElements\n",
       "node tag 1 is also"},
  };
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const TetReadResult r =
        read_tet_mesh(write_temp("bad" + std::to_string(i) + ".msh", cases[i].first));
    ASSERT_FALSE(r.report.ok()) << "case " << i;
    const std::string message = r.report.defects.front().message;
    EXPECT_NE(message.find(cases[i].second), std::string::npos) << "case " << i << ": " << message;
    EXPECT_NE(message.find("bad" + std::to_string(i) + ".msh"), std::string::npos) << message;
  }
}

// ---- TetGen --------------------------------------------------------------------------------------

TEST(TetGen, RoundTripsThroughTheProjectsReaderFromEitherName) {
  const TetMesh mesh = sample_mesh();
  const TetGenTexts texts = format_tetgen(mesh);
  const auto [node_path, ele_path] = tetgen_paths(temp_path("round.node"));
  EXPECT_EQ(ele_path, temp_path("round.ele"));
  write_temp("round.node", texts.node);
  write_temp("round.ele", texts.ele);
  for (const std::string& path : {node_path, ele_path}) {
    const TetReadResult r = read_tet_mesh(path);
    ASSERT_TRUE(r.report.ok()) << r.report.summary();
    EXPECT_EQ(r.mesh.vertices, mesh.vertices);
    EXPECT_EQ(r.mesh.tets, mesh.tets);
    EXPECT_EQ(r.mesh.reference, mesh.reference);
    EXPECT_EQ(r.reoriented, 0u);
  }
}

TEST(TetGen, OneBasedRecordsWithTheReferenceAsRegionAttribute) {
  // Read as TetGen documents it: header 'N 3 0 0' / 'M 4 1', records 'i x y z' / 'i a b c d r'.
  const TetMesh mesh = sample_mesh();
  const TetGenTexts texts = format_tetgen(mesh);
  auto records = [](const std::string& text) {
    std::vector<std::vector<std::string>> rows;
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line)) {
      if (line.empty() || line[0] == '#') continue;
      std::istringstream words(line);
      std::vector<std::string> row;
      for (std::string w; words >> w;) row.push_back(w);
      rows.push_back(row);
    }
    return rows;
  };
  const auto node = records(texts.node);
  const auto ele = records(texts.ele);
  ASSERT_EQ(node.size(), mesh.vertices.size() + 1);
  EXPECT_EQ(node[0], (std::vector<std::string>{std::to_string(mesh.vertices.size()), "3", "0", "0"}));
  ASSERT_EQ(ele.size(), mesh.tets.size() + 1);
  EXPECT_EQ(ele[0], (std::vector<std::string>{std::to_string(mesh.tets.size()), "4", "1"}));
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    ASSERT_EQ(node[v + 1].size(), 4u);
    EXPECT_EQ(node[v + 1][0], std::to_string(v + 1));
    for (int k = 0; k < 3; ++k) EXPECT_EQ(std::stod(node[v + 1][k + 1]), mesh.vertices[v][k]);
  }
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    ASSERT_EQ(ele[t + 1].size(), 6u);
    EXPECT_EQ(ele[t + 1][0], std::to_string(t + 1));
    for (int k = 0; k < 4; ++k) EXPECT_EQ(std::stoi(ele[t + 1][k + 1]), mesh.tets[t][k] + 1);
    EXPECT_EQ(std::stoi(ele[t + 1][5]), mesh.reference[t]);
  }
}

TEST(MeshFormats, ExtensionsAndPaths) {
  EXPECT_TRUE(is_tet_mesh_extension("a.msh"));
  EXPECT_TRUE(is_tet_mesh_extension("a.MSH"));
  EXPECT_EQ(tetgen_paths("dir/x.ELE"), (std::array<std::string, 2>{"dir/x.node", "dir/x.ELE"}));
  EXPECT_EQ(tetgen_paths("x.node"), (std::array<std::string, 2>{"x.node", "x.ele"}));
}

}  // namespace
}  // namespace imm::dim3
