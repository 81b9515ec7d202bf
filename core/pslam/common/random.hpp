#pragma once
// Seeded random streams. Every particle and step draws from its own stream derived from
// (seed, step, index), so results do not depend on thread scheduling.
#include <cstdint>
#include <random>

namespace pslam {

inline std::uint64_t SplitMix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

inline std::mt19937_64 MakeStream(std::uint64_t seed, std::uint64_t step, std::uint64_t index) {
  return std::mt19937_64(SplitMix64(seed ^ SplitMix64(step ^ SplitMix64(index))));
}

}  // namespace pslam
