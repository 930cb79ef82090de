// The probe table of each compiled level.
#include "lane_probes.h"

#include <string>

#include "kernels/isa_list.h"

namespace pt {
#define PT_DECLARE_TABLE(ns, level) \
  namespace ns {                    \
  extern const test::LaneProbes kLaneProbes; \
  }
PT_FOR_EACH_COMPILED_ISA(PT_DECLARE_TABLE)
#undef PT_DECLARE_TABLE
}  // namespace pt

namespace pt::test {

const LaneProbes& lane_probes(Isa isa) {
#define PT_TABLE_OF(ns, level) \
  if (isa == Isa::level) return ns::kLaneProbes;
  PT_FOR_EACH_COMPILED_ISA(PT_TABLE_OF)
#undef PT_TABLE_OF
  throw IsaError("no lane probes for " + std::string(isa_name(isa)));
}

}  // namespace pt::test
