// Technique drivers: smoothie family (not yet written).
#include "driver_util.hpp"

namespace sk {

void add_smoothie_techniques(std::vector<std::unique_ptr<Technique>>& out) { (void)out; }

}  // namespace sk
