// Instruction-set levels. The SIMD kernels (BVH traversal, the wavefront's
// stages, packets) are compiled once per level into one binary, each copy in
// namespace pt::isa_<level> behind a small table of entry points; the rest of
// the program is compiled once, for the lowest level. At start-up the widest
// level the CPU runs is picked, unless PT_ISA (environment) or `--isa` names
// one. x86-64: sse4.2 (x86-64-v2, 4 lanes), avx2 (x86-64-v3: AVX2 + FMA, 8
// lanes), avx512 (x86-64-v4, 16 lanes); aarch64: neon (4 lanes).
#pragma once

#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>

namespace pt {

enum class Isa : uint8_t { kSse42, kAvx2, kAvx512, kNeon };

/// "sse4.2", "avx2", "avx512" or "neon".
std::string_view isa_name(Isa isa);
/// The level a name (as isa_name prints it) denotes, if any.
std::optional<Isa> isa_from_name(std::string_view name);
/// Lanes of the uniform stages' batches at this level.
std::size_t isa_lanes(Isa isa);

/// The levels compiled into this binary, narrowest first.
std::span<const Isa> compiled_isas();
/// Whether this CPU (and its operating system) runs code of this level.
bool cpu_supports(Isa isa);
/// The widest compiled level this CPU runs.
Isa best_isa();

/// A level that cannot be used here: not compiled in, or not run by this CPU.
struct IsaError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// The level in use: the one set_active_isa() chose, else PT_ISA ("auto" or a
/// level name) on first use, else best_isa(). Throws IsaError when PT_ISA
/// names an unknown or unusable level.
Isa active_isa();
/// Uses `isa` from now on (objects built before keep the level they took).
/// Throws IsaError when it is not compiled in or the CPU lacks it.
void set_active_isa(Isa isa);
/// "auto" or a level name -> the level it selects here; throws IsaError.
Isa resolve_isa(std::string_view name);

/// The table of `isa` among `tables`, one per compiled level in
/// compiled_isas() order (PT_ISA_TABLE_ADDRESSES, generated/kernels/simd/isa_list.h).
/// Throws IsaError, naming `what`, for a level this binary lacks.
template <class Table>
const Table& isa_table(Isa isa, std::initializer_list<const Table*> tables, std::string_view what) {
  std::span<const Isa> levels = compiled_isas();
  for (size_t i = 0; i < levels.size() && i < tables.size(); ++i)
    if (levels[i] == isa) return *tables.begin()[i];
  throw IsaError("this binary has no " + std::string(what) + " for " + std::string(isa_name(isa)));
}

}  // namespace pt
