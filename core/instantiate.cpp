// Explicit instantiations of the dimension-generic core for d = 2 and d = 3 (CONVENTIONS:
// "explicit instantiation for D = 2, 3 in one file, extern template elsewhere").
#include "core/cell_complex_impl.h"
#include "core/graph_search_impl.h"

namespace imm {
template class CellComplex<2>;
template class CellComplex<3>;

template std::string canonical_form<2>(const CellComplex<2>&, const Immersion&);
template std::string canonical_form<3>(const CellComplex<3>&, const Immersion&);
template SearchResult find_immersions<2>(const CellComplex<2>&, const SearchOptions&);
template SearchResult find_immersions<3>(const CellComplex<3>&, const SearchOptions&);
template std::optional<Conflict> check_rules<2>(const CellComplex<2>&, const Immersion&);
template std::optional<Conflict> check_rules<3>(const CellComplex<3>&, const Immersion&);
}  // namespace imm
