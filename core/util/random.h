#pragma once
/// A small seeded pseudo-random generator whose output is the same on every
/// machine and every standard library: built-in scenes, seeded test rays and
/// benchmarks use it so that "seed 7" means the same numbers everywhere.
///
/// Why not <random>? std::mt19937_64 itself is portable, but the distributions
/// (std::uniform_real_distribution and friends) are implementation-defined, so
/// libstdc++ and libc++ give different floats for the same seed.
///
/// The algorithm is SplitMix64 (Steele, Lea & Flood, "Fast splittable
/// pseudorandom number generators", OOPSLA 2014): a 64-bit counter advanced by
/// the golden-ratio constant and passed through a bijective mixing function.
/// Every seed is fine, including 0. Not for cryptography.

#include <cstdint>

namespace accelviz {

struct Rng {
    uint64_t state = 0;  ///< the whole generator state; copy an Rng to fork the sequence

    constexpr explicit Rng(uint64_t seed = 0) : state(seed) {}

    /// The next 64 uniformly distributed bits.
    constexpr uint64_t next_u64() {
        state += 0x9e3779b97f4a7c15ull;
        uint64_t z = state;
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
        return z ^ (z >> 31);
    }

    /// Uniform in [0, 1): the top 53 bits as a multiple of 2^-53 (exact).
    constexpr double next_unit_double() { return double(next_u64() >> 11) * 0x1.0p-53; }

    /// Uniform in [0, 1): the top 24 bits as a multiple of 2^-24 (exact).
    constexpr float next_unit_float() { return float(next_u64() >> 40) * 0x1.0p-24f; }

    /// Uniform in [a, b] (a + (b - a) * u with u in [0, 1); rounding can give b
    /// itself). Pass both bounds as double; two overloads so that the result
    /// has the precision the caller works in.
    constexpr double uniform(double a, double b) { return a + (b - a) * next_unit_double(); }
    /// Uniform in [a, b] in single precision; one next_u64() per call, like the double version.
    constexpr float uniform(float a, float b) { return a + (b - a) * next_unit_float(); }

    /// Uniform integer in [0, n) for n > 0: the high 64 bits of next_u64() * n
    /// (Lemire's multiply-shift; the bias is below n / 2^64, far too small to
    /// matter here). Returns 0 for n == 0.
    constexpr uint64_t below(uint64_t n) { return mul_high(next_u64(), n); }

    /// High 64 bits of the 128-bit product a * b, in portable C++ (no __int128).
    static constexpr uint64_t mul_high(uint64_t a, uint64_t b) {
        const uint64_t a_lo = a & 0xffffffffu, a_hi = a >> 32;
        const uint64_t b_lo = b & 0xffffffffu, b_hi = b >> 32;
        const uint64_t lo_lo = a_lo * b_lo, hi_lo = a_hi * b_lo;
        const uint64_t lo_hi = a_lo * b_hi, hi_hi = a_hi * b_hi;
        const uint64_t middle = (lo_lo >> 32) + (hi_lo & 0xffffffffu) + lo_hi;
        return hi_hi + (hi_lo >> 32) + (middle >> 32);
    }
};

}  // namespace accelviz
