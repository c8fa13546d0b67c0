// The records a kernel of K uses from the program (engine/engine_export.hpp).
#include "engine/settlement_records.hpp"

namespace cs {

template class SettlementRecords<2>;
template class SettlementRecords<4>;
template class SettlementRecords<6>;

}  // namespace cs
