#include "deform/vtu.h"

#include <limits>
#include <sstream>

namespace imm::deform {

std::string format_vtu(const Eigen::MatrixXd& vertices, const Eigen::MatrixXi& elements, const VtuFields& fields) {
  std::ostringstream os;
  os.precision(std::numeric_limits<double>::max_digits10);
  // VTK cell types by corner count: 3 -> VTK_TRIANGLE (5), 4 -> VTK_TETRA (10).
  const int cell_type = elements.cols() == 3 ? 5 : 10;
  os << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
     << "<UnstructuredGrid>\n<Piece NumberOfPoints=\"" << vertices.rows() << "\" NumberOfCells=\"" << elements.rows()
     << "\">\n<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
  for (Eigen::Index v = 0; v < vertices.rows(); ++v) {
    for (Eigen::Index a = 0; a < 3; ++a) os << (a ? " " : "") << (a < vertices.cols() ? vertices(v, a) : 0.0);
    os << '\n';
  }
  os << "</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
  for (Eigen::Index e = 0; e < elements.rows(); ++e) {
    for (Eigen::Index i = 0; i < elements.cols(); ++i) os << (i ? " " : "") << elements(e, i);
    os << '\n';
  }
  os << "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
  for (Eigen::Index e = 0; e < elements.rows(); ++e) os << (e + 1) * elements.cols() << '\n';
  os << "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
  for (Eigen::Index e = 0; e < elements.rows(); ++e) os << cell_type << '\n';
  os << "</DataArray>\n</Cells>\n";
  if (!fields.point_scalars.empty()) {
    os << "<PointData>\n";
    for (const auto& [name, values] : fields.point_scalars) {
      os << "<DataArray type=\"Float64\" Name=\"" << name << "\" format=\"ascii\">\n";
      for (Eigen::Index v = 0; v < values.size(); ++v) os << values[v] << '\n';
      os << "</DataArray>\n";
    }
    os << "</PointData>\n";
  }
  if (!fields.cell_integers.empty()) {
    os << "<CellData>\n";
    for (const auto& [name, values] : fields.cell_integers) {
      os << "<DataArray type=\"Int32\" Name=\"" << name << "\" format=\"ascii\">\n";
      for (int value : values) os << value << '\n';
      os << "</DataArray>\n";
    }
    os << "</CellData>\n";
  }
  os << "</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
  return os.str();
}

}  // namespace imm::deform
