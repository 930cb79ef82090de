// The benchmark's query table of each compiled level (bench_queries.h).
#include "bench_queries.h"

#include "kernels/simd/isa_list.h"
#include "watertight_blocks.h"

namespace pt {
PT_DECLARE_ISA_TABLES(bench::BenchQueryTable, kBenchQueries)
}  // namespace pt

namespace pt::bench {

const BenchQueryTable& bench_queries() {
  return isa_table(active_isa(), {PT_ISA_TABLE_ADDRESSES(kBenchQueries)}, "benchmark queries");
}

WatertightBvh4::WatertightBvh4(const Scene& scene, const Bvh4Options& options)
    : bvh_(scene, options), tree_(to_watertight(bvh_.bvh(), scene.positions, scene.triangles)) {}

}  // namespace pt::bench
