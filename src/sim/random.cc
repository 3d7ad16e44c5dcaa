#include "plumb/random.h"

#include <cmath>

namespace plumb {

std::array<std::uint32_t, 4> Philox4x32(std::array<std::uint32_t, 4> c, std::uint64_t key) {
  // the round multipliers and Weyl key increments of Philox4x32
  constexpr std::uint64_t kM0 = 0xD2511F53, kM1 = 0xCD9E8D57;
  constexpr std::uint32_t kW0 = 0x9E3779B9, kW1 = 0xBB67AE85;
  std::uint32_t k0 = static_cast<std::uint32_t>(key), k1 = static_cast<std::uint32_t>(key >> 32);
  for (int round = 0; round < 10; ++round) {
    std::uint64_t p0 = kM0 * c[0], p1 = kM1 * c[2];
    c = {static_cast<std::uint32_t>(p1 >> 32) ^ c[1] ^ k0, static_cast<std::uint32_t>(p1),
         static_cast<std::uint32_t>(p0 >> 32) ^ c[3] ^ k1, static_cast<std::uint32_t>(p0)};
    k0 += kW0;
    k1 += kW1;
  }
  return c;
}

namespace {
std::array<std::uint32_t, 4> Block(std::uint64_t seed, std::uint64_t stream, std::uint32_t key,
                                   std::uint32_t counter) {
  return Philox4x32(
      {counter, key, static_cast<std::uint32_t>(stream), static_cast<std::uint32_t>(stream >> 32)},
      seed);
}

// 53 random bits -> (0, 1): never exactly 0, so logarithms are safe
double ToUnit(std::uint32_t hi, std::uint32_t lo) {
  std::uint64_t bits = (static_cast<std::uint64_t>(hi) << 21) ^ (lo >> 11);
  return (static_cast<double>(bits & ((1ULL << 53) - 1)) + 0.5) * 0x1.0p-53;
}
}  // namespace

double Uniform01(std::uint64_t seed, std::uint64_t stream, std::uint32_t key,
                 std::uint32_t counter) {
  std::array<std::uint32_t, 4> r = Block(seed, stream, key, counter);
  return ToUnit(r[0], r[1]);
}

double StandardNormal(std::uint64_t seed, std::uint64_t stream, std::uint32_t key,
                      std::uint32_t counter) {
  std::array<std::uint32_t, 4> r = Block(seed, stream, key, counter);
  double u1 = ToUnit(r[0], r[1]), u2 = ToUnit(r[2], r[3]);
  return std::sqrt(-2 * std::log(u1)) * std::cos(2 * M_PI * u2);
}

}  // namespace plumb
