// Technique drivers: linear family (not yet written).
#include "driver_util.hpp"

namespace sk {

void add_linear_techniques(std::vector<std::unique_ptr<Technique>>& out) { (void)out; }

}  // namespace sk
