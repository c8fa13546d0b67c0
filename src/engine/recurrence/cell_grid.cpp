// The grids a kernel of K uses from the program (engine/engine_export.hpp).
#include "engine/recurrence/cell_grid.hpp"

namespace cs {

template class CellGrid<2>;
template class CellGrid<4>;
template class CellGrid<6>;

}  // namespace cs
