// The probe table of each compiled level.
#include "support/lane_probes.h"

#include "kernels/simd/isa_list.h"

namespace pt {
PT_DECLARE_ISA_TABLES(test::LaneProbes, kLaneProbes)
}  // namespace pt

namespace pt::test {

const LaneProbes& lane_probes(Isa isa) { return isa_table(isa, {PT_ISA_TABLE_ADDRESSES(kLaneProbes)}, "lane probes"); }

}  // namespace pt::test
