// Counter-based random numbers: every draw is a pure function of (seed, stream, key,
// counter), so results never depend on thread count, shard split or order.
//
// The generator is Philox4x32-10 (Salmon et al., "Parallel random numbers: as easy as
// 1, 2, 3", SC11), the counter-based generator of Random123, cuRAND and JAX.
//
// Example:
//   double u = plumb::Uniform01(seed, rollout_index, parameter_index, 0);   // in (0, 1)
//
// Thread-safety: every function is pure (no state, no allocation): call them from any thread.
// Nothing here throws.

#ifndef PLUMB_INCLUDE_PLUMB_RANDOM_H_
#define PLUMB_INCLUDE_PLUMB_RANDOM_H_

#include <array>
#include <cstdint>

namespace plumb {

// One Philox4x32-10 block: four 32-bit outputs for a 128-bit counter and a 64-bit key.
std::array<std::uint32_t, 4> Philox4x32(std::array<std::uint32_t, 4> counter, std::uint64_t key);

// A uniform double in the open interval (0, 1) for (seed, stream, key, counter), with 53
// random bits. `stream` is e.g. a rollout index, `key` a parameter index, `counter` the
// draw number for that parameter.
double Uniform01(std::uint64_t seed, std::uint64_t stream, std::uint32_t key,
                 std::uint32_t counter);

// A standard normal deviate (Box-Muller on two uniforms of the same block family).
double StandardNormal(std::uint64_t seed, std::uint64_t stream, std::uint32_t key,
                      std::uint32_t counter);

}  // namespace plumb

#endif  // PLUMB_INCLUDE_PLUMB_RANDOM_H_
