// The query table of each compiled instruction-set level.
#include "bvh4_query_table.h"

#include "kernels/simd/isa_list.h"

namespace pt {

PT_DECLARE_ISA_TABLES(Bvh4QueryTable, kBvh4Queries)

const Bvh4QueryTable& bvh4_query_table(Isa isa) {
  return isa_table(isa, {PT_ISA_TABLE_ADDRESSES(kBvh4Queries)}, "BVH4 queries");
}

}  // namespace pt
