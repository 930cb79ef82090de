// Owen-scrambled, shuffled 2D Sobol points (Burley 2020, "Practical Hash-based
// Owen Scrambling"): sample i of a pixel's dimension pair is the first two
// Sobol dimensions at a hashed-shuffled index, each coordinate nested-uniform
// scrambled by a hash-based Laine-Karras permutation. Every (pixel, bounce,
// dimension) pair has its own seed, so pairs are decorrelated ("padded") and
// the points stay a pure function of their key. Lane-generic.
#pragma once

#include <array>
#include <cstdint>
#include <type_traits>

#include "random.h"

namespace pt {

namespace sobol_detail {

/// Direction numbers of Sobol dimension 1 (primitive polynomial x + 1).
constexpr std::array<uint32_t, 32> dimension1() {
  std::array<uint32_t, 32> v{};
  v[0] = 1u << 31;
  for (int k = 1; k < 32; ++k) v[k] = v[k - 1] ^ (v[k - 1] >> 1);
  return v;
}
inline constexpr std::array<uint32_t, 32> kDim1 = dimension1();

}  // namespace sobol_detail

template <class U> inline U reverse_bits32(U x) {
  x = ((x >> 1) & U(0x55555555u)) | ((x & U(0x55555555u)) << 1);
  x = ((x >> 2) & U(0x33333333u)) | ((x & U(0x33333333u)) << 2);
  x = ((x >> 4) & U(0x0F0F0F0Fu)) | ((x & U(0x0F0F0F0Fu)) << 4);
  x = ((x >> 8) & U(0x00FF00FFu)) | ((x & U(0x00FF00FFu)) << 8);
  return (x >> 16) | (x << 16);
}

/// Burley's hash-based Laine-Karras permutation: a random permutation of the
/// binary tree of x's bits, taken from the least significant bit upwards.
template <class U> inline U laine_karras_permutation(U x, U seed) {
  x += seed;
  x ^= x * U(0x6c50b47cu);
  x ^= x * U(0xb82f1e52u);
  x ^= x * U(0xc7afe638u);
  x ^= x * U(0x8d22f6e6u);
  return x;
}

/// Owen (nested uniform) scrambling of the bits of x, most significant first.
template <class U> inline U nested_uniform_scramble(U x, U seed) {
  return reverse_bits32(laine_karras_permutation(reverse_bits32(x), seed));
}

/// Sobol dimension 1 of `index` (dimension 0 is reverse_bits32(index)).
template <class U> inline U sobol_dimension1(U index) {
  U x(0u);
  for (int bit = 0; bit < 32; ++bit) {
    U set = (index >> bit) & U(1u);
    x ^= (U(0u) - set) & U(sobol_detail::kDim1[bit]);  // all ones where the bit is set
  }
  return x;
}

/// Point `index` of the scrambled 2D sequence with this seed, in [0, 1)^2.
template <class U, class F> inline void owen_sobol_2d(U index, U seed, F& u1, F& u2) {
  U i = nested_uniform_scramble(index, seed);
  U s1 = hash32(seed ^ U(0x68bc21ebu)), s2 = hash32(seed ^ U(0x02e5be93u));
  U x = nested_uniform_scramble(reverse_bits32(i), s1);
  U y = nested_uniform_scramble(sobol_dimension1(i), s2);
  u1 = bits_to_unit<U, F>(x);
  u2 = bits_to_unit<U, F>(y);
}

}  // namespace pt
