// The query table of each compiled instruction-set level.
#include "bvh4_query_table.h"

#include <string>

#include "kernels/isa_list.h"

namespace pt {

#define PT_DECLARE_TABLE(ns, level) \
  namespace ns {                    \
  extern const Bvh4QueryTable kBvh4Queries; \
  }
PT_FOR_EACH_COMPILED_ISA(PT_DECLARE_TABLE)
#undef PT_DECLARE_TABLE

const Bvh4QueryTable& bvh4_query_table(Isa isa) {
#define PT_TABLE_OF(ns, level) \
  if (isa == Isa::level) return ns::kBvh4Queries;
  PT_FOR_EACH_COMPILED_ISA(PT_TABLE_OF)
#undef PT_TABLE_OF
  throw IsaError("this binary has no BVH4 queries for " + std::string(isa_name(isa)));
}

}  // namespace pt
