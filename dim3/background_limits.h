// The largest background mesh the 3D mesher takes, shared by the reader of background files
// (dim3/tet_io.cpp: refused at the file's header, before any record is read) and the mesher
// itself (dim3/virtual_tets.cpp: any background, generated, graded, read or passed by the C++
// API). Its own header so that neither widely included header (tet_mesh.h, mesh3.h) changes.
#pragma once

#include <cstddef>

namespace imm::dim3 {

/// Most tets a background may have: face pairing names face f of tet t by the 32-bit number
/// 4 t + f and reserves the two largest values as marks, so 4 t + 3 must stay below 2^32 - 2,
/// and 2^30 - 1 tets is the bound (a 2^30-tet background is also ~100 GB of meshing memory).
inline constexpr std::size_t kMaxBackgroundTets = (std::size_t{1} << 30) - 1;

}  // namespace imm::dim3
