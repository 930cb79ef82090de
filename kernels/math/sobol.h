// Owen-scrambled, shuffled Sobol points (Burley 2020, "Practical Hash-based
// Owen Scrambling"), the padded construction pbrt-v4 also uses: sample i of a
// pixel's dimension pair is the first two Sobol dimensions at a
// hash-shuffled index, each coordinate nested-uniform scrambled by a
// Laine-Karras permutation (after Vegdahl's hash, as pbrt-v4's FastOwenScrambler).
// Every (pixel, bounce, dimension) has its own seed, so pairs are
// decorrelated ("padded") and a point is a pure function of its key. The
// first 2^k points of a pair are a (0, k, 2)-net: stratified in every
// elementary interval of area 2^-k. Lane-generic: U is uint32_t or a batch.
#pragma once

#include <cstdint>

#include "kernels/simd/isa_namespace.h"
#include "kernels/math/random.h"

namespace pt {
inline namespace PT_ISA_NS {

/// The bits of x in reverse order (bit 0 <-> bit 31), for any lane type.
template <class U>
inline U reverse_bits32(U x) {
  x = ((x >> 1) & U(0x55555555u)) | ((x & U(0x55555555u)) << 1);
  x = ((x >> 2) & U(0x33333333u)) | ((x & U(0x33333333u)) << 2);
  x = ((x >> 4) & U(0x0F0F0F0Fu)) | ((x & U(0x0F0F0F0Fu)) << 4);
  x = ((x >> 8) & U(0x00FF00FFu)) | ((x & U(0x00FF00FFu)) << 8);
  return (x >> 16) | (x << 16);
}
inline uint32_t reverse_bits32(uint32_t x) {
  x = __builtin_bswap32(x);
  x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
  x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
  return ((x >> 4) & 0x0F0F0F0Fu) | ((x & 0x0F0F0F0Fu) << 4);
}
#if PT_PER_LEVEL
inline vuintK reverse_bits32(vuintK x) { return reverse_bits(x); }  // byte shuffles (simd.h)
#endif

/// A Laine-Karras permutation: a hash whose bit k depends only on bits <= k
/// of x, so reversed it permutes a binary tree of intervals from the top
/// down, as Owen scrambling does. Two multiplies of Vegdahl's form (a seeded
/// add, a seeded odd multiply, an even-constant xor-multiply): the error of
/// points scrambled by it matches true nested uniform scrambling, which
/// tests/kernels/test_sobol.cpp checks.
template <class U>
inline U laine_karras_permutation(U x, U seed) {
  x += seed;
  x *= (seed >> 16) | U(1u);
  x ^= x * U(0x05526c56u);
  return x;
}

/// Owen (nested uniform) scrambling of the bits of x, most significant first.
template <class U>
inline U nested_uniform_scramble(U x, U seed) {
  return reverse_bits32(laine_karras_permutation(reverse_bits32(x), seed));
}

/// Sobol dimension 1 of `index` with its bits reversed. Dimension 1's
/// generator matrix is Pascal's triangle mod 2: output bit j (counted from the
/// top) is the parity of the index bits b whose binary digits include j's
/// (Lucas), a superset-sum transform done in five shift-and-xor steps.
template <class U>
inline U sobol_dimension1_reversed(U index) {
  index ^= (index >> 1) & U(0x55555555u);
  index ^= (index >> 2) & U(0x33333333u);
  index ^= (index >> 4) & U(0x0F0F0F0Fu);
  index ^= (index >> 8) & U(0x00FF00FFu);
  index ^= (index >> 16) & U(0x0000FFFFu);
  return index;
}

/// Sobol dimension 1 of `index` (dimension 0 is reverse_bits32(index)).
template <class U>
inline U sobol_dimension1(U index) {
  return reverse_bits32(sobol_dimension1_reversed(index));
}

/// The seeds of a shuffled, scrambled sequence: one for the index shuffle, one
/// per coordinate's scramble. The scramble seeds are cheap bijections of the
/// shuffle's (a rotation, an odd multiple): each Laine-Karras permutation
/// reads different bits of its seed for its top-level flips, and
/// tests/kernels/test_sobol.cpp checks that the error of the scrambled points is that
/// of independently hashed seeds.
template <class U>
struct SobolSeeds {
  U shuffle, scramble_x, scramble_y;
  explicit SobolSeeds(U seed)
      : shuffle(seed), scramble_x((seed >> 16) | (seed << 16)), scramble_y(seed * U(0x9e3779b9u)) {}
};

/// The shuffled index: `index` nested-uniform scrambled (a random permutation
/// that maps every aligned block of 2^k indices onto an aligned block of 2^k,
/// so prefixes of 2^k points stay nets). Takes the index with its bits
/// already reversed (the same for every dimension of a sample).
template <class U>
inline U shuffled_index(U index_reversed, U seed) {
  return reverse_bits32(laine_karras_permutation(index_reversed, seed));
}

/// Point `index` of the scrambled 2D sequence with this seed, in [0, 1)^2,
/// given reverse_bits32(index). The scrambles of dimension 0
/// (reverse_bits32(i)) and dimension 1 reverse the bits twice; the pairs
/// cancel, so each coordinate costs one reversal.
template <class U, class F>
inline void owen_sobol_2d_reversed(U index_reversed, U seed, F& u1, F& u2) {
  SobolSeeds<U> s(seed);
  U i = shuffled_index(index_reversed, s.shuffle);
  u1 = bits_to_unit<U, F>(reverse_bits32(laine_karras_permutation(i, s.scramble_x)));
  u2 = bits_to_unit<U, F>(reverse_bits32(laine_karras_permutation(sobol_dimension1_reversed(i), s.scramble_y)));
}

/// Point `index` of the scrambled 1D sequence (Sobol dimension 0, the van der
/// Corput sequence) with this seed, in [0, 1), given reverse_bits32(index).
template <class U, class F>
inline F owen_sobol_1d_reversed(U index_reversed, U seed) {
  SobolSeeds<U> s(seed);
  U i = shuffled_index(index_reversed, s.shuffle);
  return bits_to_unit<U, F>(reverse_bits32(laine_karras_permutation(i, s.scramble_x)));
}

/// Point `index` of the scrambled 2D sequence with this seed, in [0, 1)^2.
template <class U, class F>
inline void owen_sobol_2d(U index, U seed, F& u1, F& u2) {
  owen_sobol_2d_reversed<U, F>(reverse_bits32(index), seed, u1, u2);
}

}  // namespace PT_ISA_NS
}  // namespace pt
