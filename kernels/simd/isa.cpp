// Instruction-set levels: names, CPU detection (CPUID and XGETBV on x86-64,
// as the x86-64 psABI defines the levels) and the level in use.
#include "kernels/simd/isa.h"

#include <array>
#include <atomic>
#include <cstdlib>

#include "kernels/simd/isa_list.h"  // generated: PT_FOR_EACH_COMPILED_ISA

#if defined(__x86_64__)
#include <cpuid.h>
#endif

namespace pt {
namespace {

struct IsaInfo {
  Isa isa;
  std::string_view name;
  std::size_t lanes;
};
constexpr std::array<IsaInfo, 4> kIsas = {{
    {Isa::kSse42, "sse4.2", 4},
    {Isa::kAvx2, "avx2", 8},
    {Isa::kAvx512, "avx512", 16},
    {Isa::kNeon, "neon", 4},
}};

#define PT_LIST_ISA(ns, level) Isa::level,
constexpr Isa kCompiled[] = {PT_FOR_EACH_COMPILED_ISA(PT_LIST_ISA)};
#undef PT_LIST_ISA

#if defined(__x86_64__)
bool bit(uint32_t reg, int b) { return (reg >> b & 1u) != 0; }

/// x86-64 microarchitecture levels 2, 3 and 4 (the psABI's lists), with the
/// operating system's support of the AVX and AVX-512 register state.
bool x86_supports(Isa isa) {
  uint32_t a, b, c, d;
  if (!__get_cpuid(1, &a, &b, &c, &d)) return false;
  const uint32_t c1 = c;
  uint32_t ext_c = 0;
  if (__get_cpuid(0x80000001u, &a, &b, &c, &d)) ext_c = c;
  const bool v2 = bit(c1, 0) && bit(c1, 9) && bit(c1, 13) && bit(c1, 19) && bit(c1, 20) && bit(c1, 23) &&
                  bit(ext_c, 0);  // SSE3 SSSE3 CX16 SSE4.1 SSE4.2 POPCNT LAHF
  if (isa == Isa::kSse42) return v2;
  if (!v2 || !bit(c1, 27)) return false;  // OSXSAVE: XGETBV reports the enabled state
  uint32_t xcr0_lo, xcr0_hi;
  asm volatile("xgetbv" : "=a"(xcr0_lo), "=d"(xcr0_hi) : "c"(0));
  uint32_t b7 = 0;
  if (__get_cpuid_count(7, 0, &a, &b, &c, &d)) b7 = b;
  const bool v3 = (xcr0_lo & 0x6u) == 0x6u && bit(c1, 12) && bit(c1, 22) && bit(c1, 28) && bit(c1, 29) && bit(b7, 3) &&
                  bit(b7, 5) && bit(b7, 8) && bit(ext_c, 5);  // FMA MOVBE AVX F16C BMI1 AVX2 BMI2 LZCNT
  if (isa == Isa::kAvx2) return v3;
  const bool v4 = v3 && (xcr0_lo & 0xE6u) == 0xE6u && bit(b7, 16) && bit(b7, 17) && bit(b7, 28) && bit(b7, 30) &&
                  bit(b7, 31);  // AVX512 F DQ CD BW VL
  return isa == Isa::kAvx512 && v4;
}
#endif

bool compiled(Isa isa) {
  for (Isa c : kCompiled)
    if (c == isa) return true;
  return false;
}

/// Why `isa` cannot be used here, or "" when it can.
std::string unusable_because(Isa isa) {
  if (!compiled(isa)) {
    std::string list;
    for (Isa c : kCompiled) list += (list.empty() ? "" : ", ") + std::string(isa_name(c));
    return "this binary is not compiled for " + std::string(isa_name(isa)) + " (it has: " + list + ")";
  }
  if (!cpu_supports(isa)) return "this CPU does not support " + std::string(isa_name(isa));
  return "";
}

constexpr int kUnset = -1;
std::atomic<int> g_active{kUnset};

}  // namespace

std::string_view isa_name(Isa isa) { return kIsas[static_cast<std::size_t>(isa)].name; }

std::size_t isa_lanes(Isa isa) { return kIsas[static_cast<std::size_t>(isa)].lanes; }

std::optional<Isa> isa_from_name(std::string_view name) {
  for (const IsaInfo& i : kIsas)
    if (i.name == name) return i.isa;
  return std::nullopt;
}

std::span<const Isa> compiled_isas() { return kCompiled; }

bool cpu_supports(Isa isa) {
#if defined(__x86_64__)
  return isa != Isa::kNeon && x86_supports(isa);
#else
  return isa == Isa::kNeon;  // Advanced SIMD is part of every AArch64 CPU
#endif
}

Isa best_isa() {
  Isa best = kCompiled[0];
  bool found = false;
  for (Isa isa : kCompiled)
    if (cpu_supports(isa)) best = isa, found = true;
  if (!found)
    throw IsaError("this CPU does not support " + std::string(isa_name(kCompiled[0])) +
                   ", the lowest level this binary is compiled for");
  return best;
}

Isa resolve_isa(std::string_view name) {
  if (name == "auto") return best_isa();
  std::optional<Isa> isa = isa_from_name(name);
  if (!isa)
    throw IsaError("unknown instruction set \"" + std::string(name) + "\" (one of: auto, sse4.2, avx2, avx512, neon)");
  if (std::string why = unusable_because(*isa); !why.empty()) throw IsaError(why);
  return *isa;
}

Isa active_isa() {
  int v = g_active.load(std::memory_order_acquire);
  if (v != kUnset) return static_cast<Isa>(v);
  const char* env = std::getenv("PT_ISA");
  Isa isa;
  try {
    isa = resolve_isa(env && *env ? env : "auto");
  } catch (const IsaError& e) { throw IsaError(std::string("PT_ISA: ") + e.what()); }
  int expected = kUnset;
  g_active.compare_exchange_strong(expected, static_cast<int>(isa), std::memory_order_acq_rel);
  return static_cast<Isa>(g_active.load(std::memory_order_acquire));
}

void set_active_isa(Isa isa) {
  if (std::string why = unusable_because(isa); !why.empty()) throw IsaError(why);
  g_active.store(static_cast<int>(isa), std::memory_order_release);
}

}  // namespace pt
