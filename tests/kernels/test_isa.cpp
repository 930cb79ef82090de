// Instruction-set levels: names, the tables compiled into this binary, CPU
// detection against what the kernel reports in /proc/cpuinfo, and the level
// in use following PT_ISA (how CI runs the whole suite at every level).
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include "bvh/bvh4_query_table.h"
#include "kernels/simd/isa.h"
#include "kernels/simd/simd.h"
#include "support/lane_probes.h"
#include "wavefront/engines.h"

namespace pt {
namespace {

constexpr Isa kAll[] = {Isa::kSse42, Isa::kAvx2, Isa::kAvx512, Isa::kNeon};

TEST(Isa, NamesRoundTrip) {
  for (Isa isa : kAll) EXPECT_EQ(isa_from_name(isa_name(isa)), isa);
  EXPECT_FALSE(isa_from_name("avx"));
  EXPECT_FALSE(isa_from_name(""));
  EXPECT_EQ(isa_lanes(Isa::kSse42), 4u);
  EXPECT_EQ(isa_lanes(Isa::kAvx2), 8u);
  EXPECT_EQ(isa_lanes(Isa::kAvx512), 16u);
  EXPECT_EQ(isa_lanes(Isa::kNeon), 4u);
}

TEST(Isa, EveryCompiledLevelHasItsOwnTables) {
  ASSERT_FALSE(compiled_isas().empty());
  for (Isa isa : compiled_isas()) {
    EXPECT_EQ(bvh4_query_table(isa).isa, isa);
    EXPECT_EQ(wf::engine_table(isa).isa, isa);
    EXPECT_EQ(test::lane_probes(isa).isa, isa);
    EXPECT_EQ(test::lane_probes(isa).lanes, isa_lanes(isa));
  }
  for (size_t i = 1; i < compiled_isas().size(); ++i)  // narrowest first, distinct code
    EXPECT_NE(&bvh4_query_table(compiled_isas()[i]), &bvh4_query_table(compiled_isas()[i - 1]));
}

TEST(Isa, UnusableLevelsAreRefusedWithTheirReason) {
  EXPECT_THROW(resolve_isa("sse5"), IsaError);
  EXPECT_EQ(resolve_isa("auto"), best_isa());
  EXPECT_TRUE(cpu_supports(best_isa()));
  for (Isa isa : kAll) {
    bool compiled = false;
    for (Isa c : compiled_isas()) compiled = compiled || c == isa;
    if (compiled && cpu_supports(isa)) {
      EXPECT_EQ(resolve_isa(isa_name(isa)), isa);
      continue;
    }
    try {
      resolve_isa(isa_name(isa));
      ADD_FAILURE() << isa_name(isa) << " was accepted";
    } catch (const IsaError& e) {
      EXPECT_NE(std::string(e.what()).find(compiled ? "this CPU does not support" : "is not compiled for"),
                std::string::npos)
          << e.what();
    }
  }
  for (Isa c : compiled_isas()) {  // auto takes the widest level the CPU runs
    if (!cpu_supports(c)) continue;
    EXPECT_GE(static_cast<int>(best_isa()), static_cast<int>(c));
  }
}

TEST(Isa, TheLevelInUseIsTheOnePT_ISANames) {
  const char* env = std::getenv("PT_ISA");
  Isa expected = resolve_isa(env && *env ? env : "auto");
  EXPECT_EQ(active_isa(), expected) << "PT_ISA=" << (env ? env : "(unset)");
}

// Against an independent implementation: GCC's run-time CPU model (libgcc's
// __builtin_cpu_supports, which knows the psABI's level names), and xsimd's
// own CPUID reading for the features it reports. (The kernel's flags in
// /proc/cpuinfo are not a reliable third opinion: some hypervisors leave
// flags out that CPUID reports.)
TEST(Isa, DetectionAgreesWithTheCompilersCpuModel) {
#if !defined(__x86_64__)
  EXPECT_TRUE(cpu_supports(Isa::kNeon));
  EXPECT_FALSE(cpu_supports(Isa::kAvx2));
#elif !defined(__GNUC__) || defined(__clang__)
  GTEST_SKIP() << "needs GCC's __builtin_cpu_supports(\"x86-64-v3\")";
#else
  __builtin_cpu_init();
  EXPECT_EQ(cpu_supports(Isa::kSse42), __builtin_cpu_supports("x86-64-v2") != 0);
  EXPECT_EQ(cpu_supports(Isa::kAvx2), __builtin_cpu_supports("x86-64-v3") != 0);
  EXPECT_EQ(cpu_supports(Isa::kAvx512), __builtin_cpu_supports("x86-64-v4") != 0);
  EXPECT_FALSE(cpu_supports(Isa::kNeon));
  xsimd::detail::supported_arch xs = xsimd::available_architectures();
  if (cpu_supports(Isa::kAvx2)) { EXPECT_TRUE(xs.avx2 && xs.fma3_avx2); }
  if (cpu_supports(Isa::kAvx512)) { EXPECT_TRUE(xs.avx512f && xs.avx512bw && xs.avx512cd && xs.avx512dq); }
#endif
}

}  // namespace
}  // namespace pt
