// Conforming immersed tet meshes (dim3/conforming_mesh3.h): the rounded cut mesh checked
// exactly, TetGen's constrained Delaunay tetrahedralization with the surface preserved, exact
// region labels, and the dimension-generic duplicate-and-connect driver (core/unglue.h) as in
// 2D conforming meshing (dim2/mesh2.cpp): every tet lies in one region, so each tet is one local
// region; tets sharing a face off the surface are connected per node, tets sharing a cut
// triangle are connected through the immersion-graph edges across its patch (declined: glued;
// owned: no edge, the owner's copy keeps the face as boundary).
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/box_intersection_d.h>

// TetGen's library interface (Debian's libtet is built with TETLIBRARY: errors are thrown ints).
#define TETLIBRARY
#include <tetgen.h>
#undef REAL

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <limits>
#include <numeric>
#include <sstream>
#include <unordered_map>

#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstring>

#include "core/union_find.h"
#include "core/unglue.h"
#include "dim3/conforming_mesh3.h"
#include "dim3/mesh3_detail.h"

namespace imm::dim3 {

namespace {

using Epick = CGAL::Exact_predicates_inexact_constructions_kernel;
using P3 = Epick::Point_3;
constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
constexpr const char* kStage = "conforming-mesh";

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

P3 point(const Point3& p) { return {p[0], p[1], p[2]}; }

/// A face as its three vertex ids, sorted (the key of face maps).
struct FaceKey {
  std::array<std::int32_t, 3> v;
  bool operator==(const FaceKey&) const = default;
};
struct FaceHash {
  std::size_t operator()(const FaceKey& k) const {
    std::uint64_t h = 1469598103934665603ull;
    for (std::int32_t x : k.v) h = (h ^ static_cast<std::uint32_t>(x)) * 1099511628211ull;
    return static_cast<std::size_t>(h);
  }
};
FaceKey key_of(std::int32_t a, std::int32_t b, std::int32_t c) {
  FaceKey k{{a, b, c}};
  std::sort(k.v.begin(), k.v.end());
  return k;
}

/// The rounded cut mesh as a piecewise linear complex: compact point ids, one facet per cut
/// triangle (oriented like it).
struct Plc {
  std::vector<P3> points;
  std::vector<std::uint32_t> geometric;          ///< per PLC point: the complex's geometric point
  std::vector<std::array<std::int32_t, 3>> facets;  ///< per cut triangle
};

/// The largest conforming tetrahedralization asked for (about the 150-cube grid's 20 million tets).
constexpr double kMaxConformingTets = 2e7;
/// TetGen's Steiner points (-S): this many per tet the volume bound asks for, plus kSteinerExtra.
constexpr std::size_t kSteinerPerTet = 2;
constexpr std::size_t kSteinerExtra = 20000;

Plc make_plc(const Complex& complex);

/// log10 of an upper bound of the volume TetGen fills: the sum of the cones' volumes from the
/// centroid of the points to the cut triangles (doubles, for the work bound only). In log10 with
/// the differences scaled by a power of two, so that neither a box of 1e300 (volume 1e900) nor
/// one of 1e-300 over- or underflows; -infinity for no volume.
double plc_volume_bound_log10(const Plc& plc) {
  double c[3] = {0, 0, 0};
  for (const P3& p : plc.points)
    for (int a = 0; a < 3; ++a) c[a] += p[a] / static_cast<double>(plc.points.size());
  double big = 0.0;
  for (const P3& p : plc.points)
    for (int a = 0; a < 3; ++a) big = std::max(big, std::abs(p[a] - c[a]));
  if (!(big > 0) || !std::isfinite(big)) return -std::numeric_limits<double>::infinity();
  const int e = std::ilogb(big);  // differences times 2^-e are below 2
  double sum = 0.0;
  for (const auto& f : plc.facets) {
    double m[3][3];
    for (int k = 0; k < 3; ++k)
      for (int a = 0; a < 3; ++a)
        m[k][a] = std::ldexp(plc.points[static_cast<std::size_t>(f[static_cast<std::size_t>(k)])][a] - c[a], -e);
    const double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                       m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    sum += std::abs(det) / 6.0;
  }
  return std::log10(sum) + 3.0 * e * std::log10(2.0);
}

/// The magnitude whose log10 is `l`, printed as `std::setprecision(digits) << 10^l` prints it,
/// also beyond the range of doubles ("4.57e+901", not "inf"); "0" for l = -infinity.
std::string format_log10(double l, int digits) {
  if (std::isinf(l) && l < 0) return "0";
  std::ostringstream out;
  if (std::abs(l) < 300) {
    out << std::setprecision(digits) << std::pow(10.0, l);
    return out.str();
  }
  if (!std::isfinite(l)) return "inf";
  double e = std::floor(l);
  char mantissa[64];
  std::snprintf(mantissa, sizeof mantissa, "%.*g", digits, std::pow(10.0, l - e));
  if (std::strtod(mantissa, nullptr) >= 10.0) {  // 9.9996 rounded up to 10
    e += 1;
    std::snprintf(mantissa, sizeof mantissa, "%.*g", digits, std::pow(10.0, l - e));
  }
  char exponent[32];
  std::snprintf(exponent, sizeof exponent, "e%c%02.0f", e < 0 ? '-' : '+', std::abs(e));
  return std::string(mantissa) + exponent;
}

Plc make_plc(const Complex& complex) {
  Plc plc;
  std::vector<std::int32_t> index(complex.points.size(), -1);
  plc.facets.reserve(complex.cut_triangles.size());
  for (const Triangle& t : complex.cut_triangles) {
    std::array<std::int32_t, 3> f{};
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t g = complex.cut_point[t[k]];
      if (index[g] < 0) {
        index[g] = static_cast<std::int32_t>(plc.points.size());
        plc.points.push_back(point(complex.points[g]));
        plc.geometric.push_back(g);
      }
      f[k] = index[g];
    }
    plc.facets.push_back(f);
  }
  return plc;
}

Defect defect(DefectKind kind, std::string message) {
  Defect d;
  d.kind = kind;
  d.stage = kStage;
  d.message = std::move(message);
  return d;
}

std::vector<double> coords(const P3& p) { return {p.x(), p.y(), p.z()}; }

/// True when direction a - v lies in the closed wedge at v spanned by c - v and d - v (all four
/// points coplanar, v, c, d not collinear): exact coplanar orientations.
bool in_wedge(const P3& v, const P3& c, const P3& d, const P3& a) {
  const CGAL::Orientation o1 = CGAL::coplanar_orientation(v, c, d, a);
  const CGAL::Orientation o2 = CGAL::coplanar_orientation(v, d, c, a);
  return o1 != CGAL::NEGATIVE && o2 != CGAL::NEGATIVE;
}

/// Whether closed triangles t1 and t2 of the PLC meet outside the vertices and edge they share
/// (exact on the doubles). @pre neither is flat; they are different triangles.
bool improper_contact(const Plc& plc, const std::array<std::int32_t, 3>& t1, const std::array<std::int32_t, 3>& t2) {
  std::array<int, 3> shared_in_1{-1, -1, -1};  // for each corner of t1: its corner in t2, or -1
  int shared = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (t1[i] == t2[j]) shared_in_1[i] = j, ++shared;
  const auto P = [&](std::int32_t v) -> const P3& { return plc.points[static_cast<std::size_t>(v)]; };
  const Epick::Triangle_3 tri1(P(t1[0]), P(t1[1]), P(t1[2]));
  const Epick::Triangle_3 tri2(P(t2[0]), P(t2[1]), P(t2[2]));
  if (shared == 0) return CGAL::do_intersect(tri1, tri2);
  if (shared >= 3) return true;  // the same triangle twice
  if (shared == 2) {
    // Common edge (a, b); c of t1 and d of t2 are the other corners. Two non-coplanar triangles
    // on one edge meet only on it; coplanar ones overlap when c and d are on the same side.
    int i = 0, j = 0;
    while (shared_in_1[i] >= 0) ++i;
    for (int k = 0; k < 3; ++k)
      if (t2[k] != t1[0] && t2[k] != t1[1] && t2[k] != t1[2]) j = k;
    const int a = (i + 1) % 3, b = (i + 2) % 3;
    const P3& pa = P(t1[a]);
    const P3& pb = P(t1[b]);
    const P3& c = P(t1[i]);
    const P3& d = P(t2[j]);
    if (CGAL::orientation(pa, pb, c, d) != CGAL::COPLANAR) return false;
    return CGAL::coplanar_orientation(pa, pb, c, d) != CGAL::NEGATIVE;
  }
  // One common vertex v: t1 = (v, a, b), t2 = (v, c, d). Their intersection is convex and
  // contains v; it holds another point exactly when some edge of one triangle meets the other
  // beyond v: the far edges by exact segment-triangle tests, the edges at v only when they lie in
  // the other triangle's plane and point into its wedge at v.
  int i = 0;
  while (shared_in_1[i] < 0) ++i;
  const int j = shared_in_1[i];
  const P3& v = P(t1[i]);
  const P3& a = P(t1[(i + 1) % 3]);
  const P3& b = P(t1[(i + 2) % 3]);
  const P3& c = P(t2[(j + 1) % 3]);
  const P3& d = P(t2[(j + 2) % 3]);
  if (CGAL::do_intersect(Epick::Segment_3(a, b), tri2)) return true;
  if (CGAL::do_intersect(Epick::Segment_3(c, d), tri1)) return true;
  for (const P3* e : {&a, &b})
    if (CGAL::orientation(v, c, d, *e) == CGAL::COPLANAR && in_wedge(v, c, d, *e)) return true;
  for (const P3* e : {&c, &d})
    if (CGAL::orientation(v, a, b, *e) == CGAL::COPLANAR && in_wedge(v, a, b, *e)) return true;
  return false;
}

/// The exact checks of the rounded cut mesh (see the header). `source[x]`: the input triangle of
/// facet x, for messages. Defects go to `report`.
void check_plc(const Plc& plc, const std::vector<std::uint32_t>& source_triangle, ValidationReport& report) {
  // Distinct exact points that round to one double point.
  {
    std::vector<std::uint32_t> order(plc.points.size());
    std::iota(order.begin(), order.end(), 0u);
    std::sort(order.begin(), order.end(), [&](std::uint32_t x, std::uint32_t y) { return plc.points[x] < plc.points[y]; });
    for (std::size_t k = 1; k < order.size(); ++k) {
      if (plc.points[order[k]] != plc.points[order[k - 1]]) continue;
      Defect d = defect(DefectKind::OutOfRange,
                        "two intersection points of the cut mesh round to the same double point " +
                            format_point({plc.points[order[k]].x(), plc.points[order[k]].y(), plc.points[order[k]].z()}) +
                            ": the intersection curves have features below double precision; the conforming mesher "
                            "(TetGen) takes doubles");
      d.points = {coords(plc.points[order[k]])};
      report.add(std::move(d));
    }
  }
  const auto P = [&](std::int32_t v) -> const P3& { return plc.points[static_cast<std::size_t>(v)]; };
  const auto source = [&](std::size_t x) { return static_cast<long>(source_triangle[x]); };
  for (std::size_t x = 0; x < plc.facets.size(); ++x) {
    const auto& f = plc.facets[x];
    if (!CGAL::collinear(P(f[0]), P(f[1]), P(f[2]))) continue;
    Defect d = defect(DefectKind::DegenerateFacet,
                      "cut triangle " + std::to_string(x) + " of input triangle " + std::to_string(source(x)) +
                          " is flat once its intersection points are rounded to doubles; the conforming mesher "
                          "(TetGen) takes doubles");
    d.facets = {source(x)};
    d.points = {coords(P(f[0])), coords(P(f[1])), coords(P(f[2]))};
    report.add(std::move(d));
  }
  if (!report.ok()) return;
  using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, std::uint32_t>;
  std::vector<Box> boxes;
  boxes.reserve(plc.facets.size());
  for (std::uint32_t x = 0; x < plc.facets.size(); ++x) {
    const auto& f = plc.facets[x];
    boxes.emplace_back(P(f[0]).bbox() + P(f[1]).bbox() + P(f[2]).bbox(), x);
  }
  std::vector<std::pair<std::uint32_t, std::uint32_t>> bad;
  CGAL::box_self_intersection_d(boxes.begin(), boxes.end(), [&](const Box& b1, const Box& b2) {
    if (improper_contact(plc, plc.facets[b1.info()], plc.facets[b2.info()]))
      bad.emplace_back(std::min(b1.info(), b2.info()), std::max(b1.info(), b2.info()));
  });
  std::sort(bad.begin(), bad.end());
  for (const auto& [x, y] : bad) {
    Defect d = defect(DefectKind::OutOfRange,
                      "cut triangles " + std::to_string(x) + " and " + std::to_string(y) + " (of input triangles " +
                          std::to_string(source(x)) + " and " + std::to_string(source(y)) +
                          ") cross or overlap once the intersection points are rounded to doubles (exact test on the "
                          "rounded points): the cut mesh has features below double precision there; the conforming "
                          "mesher (TetGen) takes doubles");
    d.facets = {source(x), source(y)};
    report.add(std::move(d));
  }
}

std::string format_number(double x) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.17g", x);
  return buffer;
}

std::string tetgen_error(int code) {
  switch (code) {
    case 1: return "out of memory";
    case 2: return "internal error";
    case 3: return "it found two facets that intersect";
    case 4: return "it found a very small input feature (below its tolerance)";
    case 5: return "it found two very close input facets";
    case 10: return "input error";
    default: return "error code " + std::to_string(code);
  }
}

/// TetGen's output: points (x, y, z each) and tets (4 point ids each), or why it failed.
struct TetgenOutput {
  std::vector<double> points;
  std::vector<std::int32_t> tets;
  std::string failure;  ///< empty on success
};

bool write_all(int fd, const void* data, std::size_t bytes) {
  const char* p = static_cast<const char*>(data);
  while (bytes > 0) {
    const ssize_t n = ::write(fd, p, bytes);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    p += n;
    bytes -= static_cast<std::size_t>(n);
  }
  return true;
}

/// Runs TetGen in a child process. TetGen 1.5 frees its memory twice when it stops on an error
/// in library mode (terminatetetgen() frees, then the unwinding destructor frees again): the
/// process would die of SIGSEGV on every bad input. The child sends the mesh through a pipe;
/// its death, exit code and printed messages become the failure text instead.
TetgenOutput run_tetgen(tetgenio& in, std::string switches) {
  TetgenOutput result;
  std::fflush(nullptr);
  std::FILE* messages = std::tmpfile();
  int fds[2];
  if (::pipe(fds) != 0) {
    result.failure = "cannot create a pipe for TetGen";
    if (messages) std::fclose(messages);
    return result;
  }
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) {
    result.failure = "cannot start a process for TetGen";
    ::close(fds[0]);
    ::close(fds[1]);
    if (messages) std::fclose(messages);
    return result;
  }
  if (pid == 0) {
    // TetGen dies with the program: a killed `immerse` (SIGTERM, SIGKILL) must not leave its
    // refinement running as an orphan (it grew by ~16 MB/s until memory ran out).
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (::getppid() != parent) ::_exit(1);
    ::close(fds[0]);
    if (messages) {
      ::dup2(::fileno(messages), 1);
      ::dup2(::fileno(messages), 2);
    }
    std::setvbuf(stdout, nullptr, _IONBF, 0);
    tetgenio out;
    int code = 0;
    try {
      tetrahedralize(switches.data(), &in, &out);
    } catch (int c) {
      code = c;
    }
    std::int64_t header[3] = {code, out.numberofpoints, code == 0 ? out.numberoftetrahedra : 0};
    if (code == 0 && out.numberofcorners != 4) header[0] = -1;
    bool ok = write_all(fds[1], header, sizeof header);
    if (ok && header[0] == 0) {
      ok = write_all(fds[1], out.pointlist, sizeof(double) * 3 * static_cast<std::size_t>(out.numberofpoints)) &&
           write_all(fds[1], out.tetrahedronlist, sizeof(int) * 4 * static_cast<std::size_t>(out.numberoftetrahedra));
    }
    ::close(fds[1]);
    ::_exit(ok ? 0 : 1);
  }
  ::close(fds[1]);
  std::vector<char> bytes;
  char buffer[1 << 16];
  for (;;) {
    const ssize_t n = ::read(fds[0], buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    bytes.insert(bytes.end(), buffer, buffer + n);
  }
  ::close(fds[0]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  std::string printed;
  if (messages) {
    std::rewind(messages);
    char line[512];
    while (std::fgets(line, sizeof line, messages)) printed += line;
    std::fclose(messages);
    while (!printed.empty() && std::isspace(static_cast<unsigned char>(printed.back()))) printed.pop_back();
    if (printed.size() > 600) printed = "..." + printed.substr(printed.size() - 600);
    for (char& ch : printed)
      if (ch == '\n') ch = ' ';
  }
  const auto fail = [&](std::string why) {
    result.failure = std::move(why) + (printed.empty() ? "" : " (TetGen: " + printed + ")");
    return result;
  };
  if (WIFSIGNALED(status))
    return fail("TetGen crashed (signal " + std::to_string(WTERMSIG(status)) +
                "; TetGen 1.5 crashes when it stops on an error)");
  std::int64_t header[3] = {0, 0, 0};
  if (bytes.size() < sizeof header) return fail("TetGen's process ended without a result");
  std::memcpy(header, bytes.data(), sizeof header);
  if (header[0] != 0) return fail(header[0] < 0 ? "TetGen returned tets with other than 4 corners" : tetgen_error(static_cast<int>(header[0])));
  const std::size_t points = static_cast<std::size_t>(header[1]), tets = static_cast<std::size_t>(header[2]);
  if (bytes.size() != sizeof header + sizeof(double) * 3 * points + sizeof(int) * 4 * tets)
    return fail("TetGen's result was cut short");
  result.points.resize(3 * points);
  result.tets.resize(4 * tets);
  std::memcpy(result.points.data(), bytes.data() + sizeof header, sizeof(double) * 3 * points);
  std::memcpy(result.tets.data(), bytes.data() + sizeof header + sizeof(double) * 3 * points, sizeof(int) * 4 * tets);
  return result;
}

/// Dihedral angles (degrees) and radius-edge ratio of a tet, in doubles (report only). Computed
/// on the edges from p[0] scaled by a power of two to about 1 (both are scale-free), so that
/// they are right at any scale: the products of a tet of 1e110 overflowed (min 90 degrees,
/// radius-edge inf) and those of a tet of 1e-110 underflowed.
void tet_quality(const std::array<Point3, 4>& p, std::array<double, 6>& angles, double& radius_edge) {
  using V = std::array<double, 3>;
  const auto sub = [](const V& a, const V& b) { return V{a[0] - b[0], a[1] - b[1], a[2] - b[2]}; };
  const auto cross = [](const V& a, const V& b) {
    return V{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
  };
  const auto dot = [](const V& a, const V& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
  std::array<V, 4> q{};
  double big = 0.0;
  for (int k = 1; k < 4; ++k) {
    q[k] = {p[k][0] - p[0][0], p[k][1] - p[0][1], p[k][2] - p[0][2]};
    for (double x : q[k]) big = std::max(big, std::abs(x));
  }
  if (big > 0 && std::isfinite(big)) {
    const int e = std::ilogb(big);
    for (int k = 1; k < 4; ++k)
      for (double& x : q[k]) x = std::ldexp(x, -e);
  }
  // Face k is opposite corner k; its outward normal. The dihedral angle at the edge shared by
  // faces i and j is pi minus the angle between their outward normals.
  std::array<V, 4> normal{};
  for (int k = 0; k < 4; ++k) {
    const int a = (k + 1) % 4, b = (k + 2) % 4, c = (k + 3) % 4;
    V n = scaled_to_unit(cross(sub(q[b], q[a]), sub(q[c], q[a])));
    if (dot(n, sub(q[k], q[a])) > 0) n = {-n[0], -n[1], -n[2]};
    const double len = std::sqrt(dot(n, n));
    normal[k] = {n[0] / len, n[1] / len, n[2] / len};
  }
  int e = 0;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j)
      angles[e++] = 180.0 - std::acos(std::clamp(dot(normal[i], normal[j]), -1.0, 1.0)) * 180.0 / M_PI;
  double shortest = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) {
      const V d = sub(q[i], q[j]);
      shortest = std::min(shortest, std::sqrt(dot(d, d)));
    }
  const auto at = [&](int k) { return P3(q[k][0], q[k][1], q[k][2]); };
  const P3 centre = CGAL::circumcenter(at(0), at(1), at(2), at(3));
  const double radius = std::sqrt(CGAL::squared_distance(centre, at(0)));
  radius_edge = radius / shortest;
}

double median(std::vector<double>& values) {
  if (values.empty()) return 0.0;
  const auto mid = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  return *mid;
}

using EdgeKey = std::uint64_t;
EdgeKey edge_key(std::int32_t a, std::int32_t b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}

using Vec = std::array<double, 3>;
Vec sub(const P3& a, const P3& b) { return {a.x() - b.x(), a.y() - b.y(), a.z() - b.z()}; }
Vec cross(const Vec& a, const Vec& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const Vec& a, const Vec& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/// Per edge of the cut mesh (PLC point ids): the smallest angle in degrees of a wedge around it
/// whose region is a cell with output tets (`kept_cell`, by CellId); edges bounding no such wedge
/// are left out. The cut triangles at the edge are sorted by the angle of their third corner
/// around it; the wedge from one to the next (counterclockwise about the edge) lies on the side of
/// the first that the rotation enters (ConformingStats::min_cell_wedge). Doubles: report only.
std::unordered_map<EdgeKey, double> cell_wedges(const Plc& plc, const Complex& complex, const std::vector<char>& kept_cell) {
  const CellComplex<3>& cc = complex.complex;
  std::unordered_map<EdgeKey, std::vector<std::uint32_t>> at_edge;
  at_edge.reserve(plc.facets.size() * 2);
  for (std::uint32_t x = 0; x < plc.facets.size(); ++x)
    for (int k = 0; k < 3; ++k) at_edge[edge_key(plc.facets[x][k], plc.facets[x][(k + 1) % 3])].push_back(x);
  std::unordered_map<EdgeKey, double> wedges;
  wedges.reserve(at_edge.size());
  std::vector<std::pair<double, std::uint32_t>> around;
  for (const auto& [key, xs] : at_edge) {
    if (xs.size() < 2) continue;
    const auto a = static_cast<std::int32_t>(key >> 32), b = static_cast<std::int32_t>(key & 0xffffffffu);
    const P3& A = plc.points[static_cast<std::size_t>(a)];
    Vec axis = scaled_to_unit(sub(plc.points[static_cast<std::size_t>(b)], A));
    const double length = std::sqrt(dot(axis, axis));
    for (double& c : axis) c /= length;
    // Per cut triangle: its third corner's direction off the edge.
    const auto off_edge = [&](std::uint32_t x) {
      std::int32_t c = -1;
      for (std::int32_t v : plc.facets[x])
        if (v != a && v != b) c = v;
      Vec w = scaled_to_unit(sub(plc.points[static_cast<std::size_t>(c)], A));
      const double along = dot(w, axis);
      for (int d = 0; d < 3; ++d) w[d] -= along * axis[d];
      return scaled_to_unit(w);
    };
    const Vec u0 = off_edge(xs[0]);
    around.clear();
    for (std::uint32_t x : xs) {
      const Vec w = off_edge(x);
      around.emplace_back(std::atan2(dot(cross(u0, w), axis), dot(u0, w)), x);
    }
    std::sort(around.begin(), around.end());
    double smallest = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < around.size(); ++i) {
      const auto [phi, x] = around[i];
      const double next = i + 1 < around.size() ? around[i + 1].first : around[0].first + 2.0 * M_PI;
      const auto& f = plc.facets[x];
      const Vec normal =
          cross(scaled_to_unit(sub(plc.points[static_cast<std::size_t>(f[1])], plc.points[static_cast<std::size_t>(f[0])])),
                scaled_to_unit(sub(plc.points[static_cast<std::size_t>(f[2])], plc.points[static_cast<std::size_t>(f[0])])));
      const PatchSides& sides = cc.sides(complex.cut_triangle_patch[x]);
      const RegionId region = dot(normal, cross(axis, off_edge(x))) > 0 ? sides.positive : sides.negative;
      const CellId cell = cc.cell_of(region);
      if (!cell.is_valid() || !kept_cell[cell.index()]) continue;
      smallest = std::min(smallest, (next - phi) * 180.0 / M_PI);
    }
    if (std::isfinite(smallest)) wedges.emplace(key, smallest);
  }
  return wedges;
}

/// The angles (degrees) of a triangle: the smallest and the largest.
std::pair<double, double> triangle_angle_range(const P3& p0, const P3& p1, const P3& p2) {
  const std::array<const P3*, 3> p{&p0, &p1, &p2};
  double lo = 180.0, hi = 0.0;
  for (int i = 0; i < 3; ++i) {
    const Vec u = scaled_to_unit(sub(*p[(i + 1) % 3], *p[i])), v = scaled_to_unit(sub(*p[(i + 2) % 3], *p[i]));
    const double angle = std::acos(std::clamp(dot(u, v) / std::sqrt(dot(u, u) * dot(v, v)), -1.0, 1.0)) * 180.0 / M_PI;
    lo = std::min(lo, angle);
    hi = std::max(hi, angle);
  }
  return {lo, hi};
}

}  // namespace

ValidationReport check_rounded_cut_mesh(const std::vector<Point3>& points,
                                        const std::vector<std::array<std::int32_t, 3>>& triangles,
                                        const std::vector<std::uint32_t>& source_triangle) {
  IMM_ASSERT(source_triangle.size() == triangles.size(), "one source per triangle");
  Plc plc;
  for (const Point3& p : points) plc.points.push_back(point(p));
  plc.facets = triangles;
  ValidationReport report;
  check_plc(plc, source_triangle, report);
  return report;
}

ConformingResult mesh_conforming(const Complex& complex, const Immersion& immersion,
                                   const ConformingOptions& options, std::size_t input_vertices,
                                   std::size_t input_triangles) {
  ConformingResult result;
  ConformingStats& stats = result.stats;
  const auto log = [&](const std::string& message) {
    if (options.progress) options.progress(message);
  };
  IMM_ASSERT(options.edge_length > 0 && std::isfinite(options.edge_length), "edge length must be positive");
  IMM_ASSERT(options.radius_edge == 0.0 || options.radius_edge >= 1.0, "radius-edge bound below 1");
  input_vertices = std::min(input_vertices, complex.surface.vertex_count());
  input_triangles = std::min(input_triangles, complex.surface.triangle_count());
  const CellComplex<3>& cc = complex.complex;

  // 1. The rounded cut mesh, checked exactly.
  auto start = std::chrono::steady_clock::now();
  const Plc plc = make_plc(complex);
  stats.plc_points = plc.points.size();
  stats.plc_triangles = plc.facets.size();
  check_plc(plc, complex.cut_triangle_source, result.report);
  stats.seconds_checks = seconds_since(start);
  if (!result.report.ok()) return result;
  log("conforming: " + std::to_string(plc.facets.size()) + " cut triangles, " + std::to_string(plc.points.size()) +
      " points (rounded cut mesh checked exactly)");

  // 2. TetGen: constrained Delaunay tetrahedralization of the PLC, surface preserved.
  start = std::chrono::steady_clock::now();
  tetgenio in;
  in.firstnumber = 0;
  in.numberofpoints = static_cast<int>(plc.points.size());
  // TetGen's predicates and volumes are doubles of degree up to 5 in the coordinates: a box of
  // 1e110 overflows them (1e550), one of 1e-110 underflows them. Outside 2^+-100 TetGen works on
  // the points times 2^-scale, which brings the box to about 1; the factor is a power of two, so
  // the points are the same doubles after scaling back (checked; else unscaled, and the check
  // after TetGen says what went wrong).
  int scale = 0;
  {
    double lo[3], hi[3];
    for (int a = 0; a < 3; ++a) lo[a] = hi[a] = plc.points.empty() ? 0.0 : plc.points[0][a];
    for (const P3& p : plc.points)
      for (int a = 0; a < 3; ++a) {
        lo[a] = std::min(lo[a], p[a]);
        hi[a] = std::max(hi[a], p[a]);
      }
    const double longest = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
    if (longest > 0 && std::isfinite(longest) && std::abs(std::ilogb(longest)) > 100) scale = std::ilogb(longest);
    for (const P3& p : plc.points)
      for (int a = 0; a < 3 && scale != 0; ++a)
        if (std::ldexp(std::ldexp(p[a], -scale), scale) != p[a]) scale = 0;
  }
  in.pointlist = new double[plc.points.size() * 3];
  for (std::size_t v = 0; v < plc.points.size(); ++v) {
    in.pointlist[3 * v] = std::ldexp(plc.points[v].x(), -scale);
    in.pointlist[3 * v + 1] = std::ldexp(plc.points[v].y(), -scale);
    in.pointlist[3 * v + 2] = std::ldexp(plc.points[v].z(), -scale);
  }
  in.numberoffacets = static_cast<int>(plc.facets.size());
  in.facetlist = new tetgenio::facet[plc.facets.size()];
  for (std::size_t x = 0; x < plc.facets.size(); ++x) {
    tetgenio::facet& f = in.facetlist[x];
    tetgenio::init(&f);
    f.numberofpolygons = 1;
    f.polygonlist = new tetgenio::polygon[1];
    tetgenio::init(&f.polygonlist[0]);
    f.polygonlist[0].numberofvertices = 3;
    f.polygonlist[0].vertexlist = new int[3];
    for (int k = 0; k < 3; ++k) f.polygonlist[0].vertexlist[k] = plc.facets[x][k];
  }
  // -p PLC, -Y keep the surface (no Steiner point on it), -M merge neither coplanar facets nor
  // close vertices (TetGen's tolerance-based merging would change the complex), -J keep every
  // point (input point ids stay output ids), -z number from 0, -Q quiet, -F no face/edge lists,
  // -q quality bound, -a volume bound.
  std::string switches = "pYMJzQF";
  if (options.radius_edge > 0) {
    switches += "q" + format_number(options.radius_edge);
    if (options.min_dihedral > 0) switches += "/" + format_number(options.min_dihedral);
  }
  const double h = options.edge_length;
  // In TetGen's coordinates (times 2^-scale).
  const double h_scaled = std::ldexp(h, -scale);
  switches += "a" + format_number(h_scaled * h_scaled * h_scaled / (6.0 * std::sqrt(2.0)));
  // Bounded work (issue 13). The tets the volume bound asks for: the domain TetGen fills lies
  // inside the cones from the centroid to the cut triangles (a ray from the centroid through an
  // enclosed point leaves through a triangle beyond it), so their volume bounds it. A tiny edge
  // length is refused here, before TetGen runs out of memory. In log10: h^3 and the volume
  // overflow doubles for boxes beyond about 1e102 (and underflow below 1e-102).
  const double volume_log10 = plc_volume_bound_log10(plc);
  const double estimate_log10 = volume_log10 - (3.0 * std::log10(h) - std::log10(6.0 * std::sqrt(2.0)));
  if (!(estimate_log10 <= std::log10(kMaxConformingTets))) {
    std::ostringstream msg;
    msg << "edge length " << h << " would fill the input (volume at most " << format_log10(volume_log10, 6)
        << ") with about " << format_log10(estimate_log10, 3) << " tets; at most " << kMaxConformingTets
        << " (raise the edge length)";
    result.report.add(defect(DefectKind::OutOfRange, msg.str()));
    return result;
  }
  const double estimate = std::pow(10.0, estimate_log10);  // at most 2e7; 0 for no volume
  // Quality refinement need not end: TetGen may not move the preserved cut triangles, and a
  // dihedral bound above ~20 degrees next to them (25 on tube-overlap) made it insert points
  // forever. -S caps the Steiner points (the meshes that finish are the same); reaching the cap
  // is a refusal, said below.
  const std::size_t steiner_cap = kSteinerPerTet * static_cast<std::size_t>(estimate) + kSteinerExtra;
  switches += "S" + std::to_string(steiner_cap);
  TetgenOutput out = run_tetgen(in, switches);
  if (!out.failure.empty()) {
    result.report.add(defect(DefectKind::OutOfRange, "TetGen (-" + switches +
                                                         ") could not tetrahedralize the rounded cut mesh: " + out.failure));
    return result;
  }
  if (out.points.size() / 3 >= plc.points.size() + steiner_cap) {
    std::ostringstream msg;
    msg << "TetGen (-" << switches << ") stopped refining after " << steiner_cap
        << " added points: the quality bound (radius-edge " << options.radius_edge;
    if (options.min_dihedral > 0) msg << ", minimum dihedral " << options.min_dihedral << " degrees";
    msg << ") is not reachable next to the preserved cut triangles; lower it";
    result.report.add(defect(DefectKind::OutOfRange, msg.str()));
    return result;
  }
  stats.seconds_tetgen = seconds_since(start);
  stats.tetgen_points = out.points.size() / 3;
  stats.tetgen_tets = out.tets.size() / 4;
  log("conforming: TetGen -" + switches + (scale != 0 ? " on the points times 2^" + std::to_string(-scale) : "") + ": " +
      std::to_string(stats.tetgen_tets) + " tets, " + std::to_string(stats.tetgen_points) + " points");

  // 3. Exact labels. Every check below is on TetGen's output doubles, with exact predicates.
  start = std::chrono::steady_clock::now();
  const auto fail = [&](const std::string& message) {
    result.report.add(defect(DefectKind::OutOfRange, message));
    result.mesh = {};
    result.embedding.clear();
    result.tetrahedralization = {};
    result.source_tet.clear();
    return result;
  };
  std::vector<Point3> vertices(stats.tetgen_points);
  for (std::size_t v = 0; v < vertices.size(); ++v)
    vertices[v] = {std::ldexp(out.points[3 * v], scale), std::ldexp(out.points[3 * v + 1], scale),
                   std::ldexp(out.points[3 * v + 2], scale)};
  for (std::size_t v = 0; v < plc.points.size(); ++v)
    if (v >= vertices.size() || point(vertices[v]) != plc.points[v])
      return fail("TetGen moved or dropped cut-mesh point " + std::to_string(v) + " " +
                  format_point({plc.points[v].x(), plc.points[v].y(), plc.points[v].z()}) +
                  (v < vertices.size() ? " (now " + format_point(vertices[v]) + ")" : ""));
  const auto VP = [&](std::int32_t v) { return point(vertices[static_cast<std::size_t>(v)]); };
  std::vector<std::array<std::int32_t, 4>> tets(stats.tetgen_tets);
  for (std::size_t t = 0; t < tets.size(); ++t) {
    auto& tet = tets[t];
    for (int k = 0; k < 4; ++k) tet[k] = out.tets[4 * t + k];
    for (int k = 0; k < 4; ++k)
      if (tet[k] < 0 || static_cast<std::size_t>(tet[k]) >= vertices.size()) return fail("TetGen tet " + std::to_string(t) + " has a bad vertex");
    const CGAL::Orientation o = CGAL::orientation(VP(tet[0]), VP(tet[1]), VP(tet[2]), VP(tet[3]));
    if (o == CGAL::ZERO) return fail("TetGen returned a flat tet (" + std::to_string(t) + ")");
    if (o == CGAL::NEGATIVE) std::swap(tet[2], tet[3]);
  }
  // Surface faces: the cut triangles by their sorted PLC points.
  std::unordered_map<FaceKey, std::uint32_t, FaceHash> facet_of;
  facet_of.reserve(plc.facets.size() * 2);
  for (std::uint32_t x = 0; x < plc.facets.size(); ++x)
    facet_of.emplace(key_of(plc.facets[x][0], plc.facets[x][1], plc.facets[x][2]), x);
  // Faces of the tets: (tet, corner opposite) pairs per face.
  std::unordered_map<FaceKey, std::array<std::uint32_t, 2>, FaceHash> faces;
  faces.reserve(tets.size() * 3);
  for (std::uint32_t t = 0; t < tets.size(); ++t)
    for (int k = 0; k < 4; ++k) {
      const auto& tet = tets[t];
      auto [it, inserted] = faces.try_emplace(key_of(tet[(k + 1) % 4], tet[(k + 2) % 4], tet[(k + 3) % 4]),
                                              std::array<std::uint32_t, 2>{t, kNone});
      if (!inserted) {
        if (it->second[1] != kNone) return fail("a face of TetGen's mesh has three tets");
        it->second[1] = t;
      }
    }
  // Per cut triangle: the tet on its negative (inner) side and on its positive side.
  std::vector<std::array<std::uint32_t, 2>> facet_tets(plc.facets.size(), {kNone, kNone});  // {inner, outer}
  UnionFind same(tets.size());
  std::vector<RegionId> seen(tets.size());  // a region a tet of the component was seen in
  std::vector<RegionId> component_region;
  bool conflict = false;
  std::vector<std::pair<std::uint32_t, RegionId>> sightings;  // (tet, region) from the surface and the hull
  for (const auto& [key, pair] : faces) {
    const auto found = facet_of.find(key);
    if (found == facet_of.end()) {
      if (pair[1] != kNone) {
        same.unite(pair[0], pair[1]);
      } else {
        // A face of TetGen's mesh on no cut triangle and with one tet: the convex hull (the carved
        // exterior stops at the surface only), so the tet lies in the unbounded region.
        sightings.emplace_back(pair[0], RegionId(0));
      }
      continue;
    }
    const std::uint32_t x = found->second;
    const auto& f = plc.facets[x];
    const PatchSides& sides = cc.sides(complex.cut_triangle_patch[x]);
    for (std::uint32_t t : pair) {
      if (t == kNone) continue;
      // The tet's corner off the face decides its side of the oriented cut triangle.
      std::int32_t apex = -1;
      for (std::int32_t v : tets[t])
        if (v != key.v[0] && v != key.v[1] && v != key.v[2]) apex = v;
      const CGAL::Orientation o = CGAL::orientation(VP(f[0]), VP(f[1]), VP(f[2]), VP(apex));
      IMM_ASSERT(o != CGAL::ZERO, "a positive tet is flat on its face");
      const bool positive = o == CGAL::POSITIVE;
      if (facet_tets[x][positive ? 1 : 0] != kNone) return fail("two tets on one side of cut triangle " + std::to_string(x));
      facet_tets[x][positive ? 1 : 0] = t;
      sightings.emplace_back(t, positive ? sides.positive : sides.negative);
    }
  }
  for (std::uint32_t x = 0; x < plc.facets.size(); ++x)
    if (facet_tets[x][0] == kNone)
      return fail("cut triangle " + std::to_string(x) + " is not a face of TetGen's mesh with a tet on its inner side");
  std::vector<RegionId> root_region(tets.size());
  for (const auto& [t, region] : sightings) {
    RegionId& r = root_region[same.find(t)];
    if (r.is_valid() && r != region) conflict = true;
    r = region;
  }
  if (conflict)
    return fail("a component of TetGen's tets lies on the sides of two different regions of the cut mesh: rounding the "
                "intersection points to doubles changed how the sheets meet (features below double precision)");
  std::vector<RegionId> region(tets.size());
  for (std::uint32_t t = 0; t < tets.size(); ++t) {
    const std::uint32_t root = same.find(t);
    if (root == t) ++stats.components;
    if (!root_region[root].is_valid()) return fail("a component of TetGen's tets touches neither the surface nor the hull");
    region[t] = root_region[root];
  }

  // 4. Atoms (one local region per tet), connections, duplicate and connect.
  std::vector<std::uint32_t> first(tets.size() + 1);
  std::iota(first.begin(), first.end(), 0u);
  AtomExpansion<3> expansion(cc, immersion, first, region, tets);
  for (const auto& [key, pair] : faces) {
    if (pair[1] == kNone) continue;
    const auto found = facet_of.find(key);
    if (found == facet_of.end()) {
      expansion.connect(pair[0], pair[1]);
    } else {
      const std::uint32_t x = found->second;
      expansion.connect_across(facet_tets[x][0], facet_tets[x][1], complex.cut_triangle_patch[x]);
    }
  }
  const UnglueInput<3>& input = expansion.input();
  const UnglueResult<3> unglued = unglue<3>(input);
  const std::vector<char> helper_node = detail::helper_nodes(complex, immersion, input_triangles);
  TetMesh& mesh = result.mesh;
  detail::EmittedCopies emitted = detail::emit_copies(unglued, helper_node, immersion.layout, cc.cell_count(), vertices,
                                                      mesh, stats.helper_tets, stats.copies_per_cell);
  const std::vector<std::uint32_t>& copy_index = emitted.copy_index;
  const std::vector<std::int32_t>& vertex_source = emitted.vertex_source;  // per output vertex: its TetGen point
  result.source_tet = std::move(emitted.source_element);
  result.tetrahedralization.vertices = vertices;
  result.tetrahedralization.tets.reserve(tets.size());
  result.tetrahedralization.reference.reserve(tets.size());
  for (std::size_t t = 0; t < tets.size(); ++t) {
    result.tetrahedralization.tets.push_back({tets[t][0], tets[t][1], tets[t][2], tets[t][3]});
    result.tetrahedralization.reference.push_back(region[t].value());
  }
  stats.output_tets = mesh.tets.size();
  stats.output_vertices = mesh.vertices.size();

  // 5. Embedding: each user vertex is a corner of the tet on the inner side of a cut triangle
  // around it, in the copy of its patch's owner (that copy's face is the boundary there).
  result.embedding.resize(input_vertices);
  std::vector<char> done(input_vertices, 0);
  std::vector<std::int32_t> plc_index(complex.points.size(), -1);
  for (std::size_t v = 0; v < plc.geometric.size(); ++v) plc_index[plc.geometric[v]] = static_cast<std::int32_t>(v);
  for (std::uint32_t x = 0; x < plc.facets.size(); ++x) {
    if (complex.cut_triangle_source[x] >= input_triangles) continue;
    for (std::int32_t v : plc.facets[x]) {
      const std::uint32_t g = plc.geometric[static_cast<std::size_t>(v)];
      if (g >= input_vertices || done[g]) continue;  // geometric points of input vertices are their ids
      const std::uint32_t tet = facet_tets[x][0];
      const std::uint32_t atom = expansion.atom(tet, immersion.owner[complex.cut_triangle_patch[x]]);
      const std::uint32_t copy = copy_index[unglued.atom_copy[atom]];
      IMM_ASSERT(copy != kNone, "a user vertex embedded in a helper box's solid");
      EmbeddedVertex3 e;
      e.element = static_cast<int>(copy);
      for (int k = 0; k < 4; ++k) e.weights[k] = tets[tet][k] == v ? 1.0 : 0.0;
      result.embedding[g] = e;
      done[g] = 1;
    }
  }
  double worst = 0.0;
  for (std::size_t v = 0; v < input_vertices; ++v) {
    if (!done[v]) {
      stats.unused_vertices.push_back(v);
      continue;
    }
    const EmbeddedVertex3& e = result.embedding[v];
    const Tet& t = mesh.tets[static_cast<std::size_t>(e.element)];
    for (int k = 0; k < 4; ++k)
      if (e.weights[k] == 1.0) {
        const Point3& p = mesh.vertices[static_cast<std::size_t>(t[k])];
        const Point3& q = complex.surface.vertices[v];
        worst = std::max(worst, std::hypot(p[0] - q[0], p[1] - q[1], p[2] - q[2]));
      }
  }
  stats.embedding_error = worst;

  // 6. Quality (report only): angles, ratios, the cell wedges that bound every mesh's minimum
  // dihedral angle, and why each sliver is there.
  std::vector<double> dihedral, ratio;
  dihedral.reserve(mesh.tets.size() * 6);
  ratio.reserve(mesh.tets.size());
  stats.min_dihedral = 180.0;
  stats.sliver_bound = options.min_dihedral > 0 ? options.min_dihedral : 5.0;
  std::vector<char> kept_cell(cc.cell_count(), 0);
  for (std::size_t c = 0; c < stats.copies_per_cell.size() && c < kept_cell.size(); ++c)
    kept_cell[c] = stats.copies_per_cell[c] > 0;
  const std::unordered_map<EdgeKey, double> wedge = cell_wedges(plc, complex, kept_cell);
  for (const auto& [key, angle] : wedge) {
    stats.min_cell_wedge = std::min(stats.min_cell_wedge, angle);
    if (angle < stats.sliver_bound) ++stats.narrow_wedge_edges;
  }
  // The cause of a sliver of TetGen's mesh (ConformingStats::slivers_in_narrow_wedge...): 1 narrow
  // wedge, 2 cap, 3 needle, 4 other; computed once per TetGen tet (its copies share it).
  std::vector<std::int8_t> cause(tets.size(), 0);
  const auto sliver_cause = [&](std::uint32_t t) {
    if (cause[t] != 0) return cause[t];
    const auto& tet = tets[t];
    std::array<Point3, 4> p{};
    for (int k = 0; k < 4; ++k) p[k] = vertices[static_cast<std::size_t>(tet[k])];
    std::array<double, 6> angles{};
    double re = 0.0;
    tet_quality(p, angles, re);
    // Angle e is at the edge shared by the faces opposite corners i < j (tet_quality's order).
    int e = 0;
    std::int8_t found = 4;
    bool narrow = false;
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j, ++e) {
        if (angles[e] >= stats.sliver_bound) continue;
        std::array<std::int32_t, 2> edge{};
        int m = 0;
        for (int k = 0; k < 4; ++k)
          if (k != i && k != j) edge[m++] = tet[k];
        const auto w = wedge.find(edge_key(edge[0], edge[1]));
        narrow = narrow || (w != wedge.end() && w->second < stats.sliver_bound);
      }
    if (narrow) {
      found = 1;
    } else {
      for (int k = 0; k < 4; ++k) {
        const auto x = facet_of.find(key_of(tet[(k + 1) % 4], tet[(k + 2) % 4], tet[(k + 3) % 4]));
        if (x == facet_of.end()) continue;
        const auto& f = plc.facets[x->second];
        const auto [lo, hi] = triangle_angle_range(plc.points[static_cast<std::size_t>(f[0])],
                                                   plc.points[static_cast<std::size_t>(f[1])],
                                                   plc.points[static_cast<std::size_t>(f[2])]);
        if (hi > 180.0 - stats.sliver_bound) found = 2;
        if (lo < stats.sliver_bound && found != 2) found = 3;
      }
    }
    return cause[t] = found;
  };
  for (std::size_t o = 0; o < mesh.tets.size(); ++o) {
    const Tet& t = mesh.tets[o];
    std::array<Point3, 4> p{};
    for (int k = 0; k < 4; ++k) p[k] = mesh.vertices[static_cast<std::size_t>(t[k])];
    std::array<double, 6> angles{};
    double re = 0.0;
    tet_quality(p, angles, re);
    for (double a : angles) {
      dihedral.push_back(a);
      stats.min_dihedral = std::min(stats.min_dihedral, a);
    }
    ratio.push_back(re);
    if (*std::min_element(angles.begin(), angles.end()) < stats.sliver_bound) {
      ++stats.slivers;
      int on_surface = 0;
      for (int k = 0; k < 4; ++k)
        on_surface += static_cast<std::size_t>(vertex_source[static_cast<std::size_t>(t[k])]) < plc.points.size();
      if (on_surface >= 3) ++stats.slivers_at_surface;
      switch (sliver_cause(static_cast<std::uint32_t>(result.source_tet[o]))) {
        case 1: ++stats.slivers_in_narrow_wedge; break;
        case 2: ++stats.slivers_on_cap; break;
        case 3: ++stats.slivers_on_needle; break;
        default: break;
      }
    }
    stats.max_radius_edge = std::max(stats.max_radius_edge, re);
  }
  if (mesh.tets.empty()) stats.min_dihedral = 0.0;
  stats.median_dihedral = median(dihedral);
  stats.median_radius_edge = median(ratio);
  stats.seconds_assembly = seconds_since(start);
  log("conforming: " + std::to_string(stats.output_tets) + " output tets, " + std::to_string(stats.output_vertices) +
      " vertices");
  return result;
}

double conforming_edge_length(const Surface& surface, int resolution) {
  if (surface.vertices.empty() || resolution <= 0) return 0.0;
  const Box3 box = bounding_box(surface);
  double longest = 0.0;
  for (int d = 0; d < 3; ++d) longest = std::max(longest, box.hi[d] - box.lo[d]);
  const double h = longest / resolution;
  return std::isfinite(h) && h > 0 ? h : 0.0;
}

}  // namespace imm::dim3
