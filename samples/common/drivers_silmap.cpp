// Technique drivers: silmap family (not yet written).
#include "driver_util.hpp"

namespace sk {

void add_silmap_techniques(std::vector<std::unique_ptr<Technique>>& out) { (void)out; }

}  // namespace sk
