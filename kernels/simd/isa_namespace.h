// The namespace of each instruction-set level. The SIMD kernels are compiled
// once per level (kernels/simd/isa.h), and a header's inline functions and
// templates are compiled again in every level that includes it. So every
// free function, template and per-level type of the project sits in
//   namespace pt { inline namespace PT_ISA_NS { ... } }
// where PT_ISA_NS is isa_sse42, isa_avx2, isa_avx512 or isa_neon in code
// compiled for that level (cmake/isa_levels.cmake defines it) and
// isa_baseline in code compiled once. Callers name them as members of pt;
// their symbols carry the level, so the linker cannot give one level's code
// another level's copy (an AVX-512 copy on a CPU without AVX-512). Types
// that cross between levels (the scene, the BVH, rays, the render job and
// the levels' entry tables) stay outside, and tests/layering checks that
// nothing else does (check_isa_symbols.py).
#pragma once

#ifndef PT_ISA_NS
#define PT_ISA_NS isa_baseline
#endif

/// Whether this translation unit is compiled for one level (its K-wide
/// types exist): PT_ISA names the level's pt::Isa enumerator.
#if defined(PT_ISA)
#define PT_PER_LEVEL 1
#else
#define PT_PER_LEVEL 0
#endif
