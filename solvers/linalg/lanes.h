// Short vectors of doubles for loops over the k columns of a row-major block (k right-hand
// sides, k sources), and the attribute that compiles a hot loop for the host's vector ISA.
// Internal to the library: vectors of C doubles are GCC/Clang vector extensions (one register
// of the ISA a function is compiled for, or several of a narrower one), loaded and stored
// unaligned. Functions taking or returning them are always inlined, so their ABI never crosses
// a call.
#pragma once

#include <cstdint>
#include <cstring>

#if defined(__GNUC__) && !defined(__clang__)
// GCC warns at every call that a vector value "changes the ABI" between ISAs: harmless, these
// functions are always inlined. Off for the rest of the including .cpp (only .cpp files of the
// library include this header).
#pragma GCC diagnostic ignored "-Wpsabi"
#endif

// IFEM_HOST_CLONES: compile a function three times, for AVX-512 (x86-64-v4), AVX2 + FMA
// (x86-64-v3) and the baseline ISA, and pick one at load time (target_clones). Off under
// AddressSanitizer (ifunc resolvers run before its runtime is set up) and off x86-64.
#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define IFEM_LANES_NO_CLONES
#endif
#endif
#if defined(__SANITIZE_ADDRESS__)
#define IFEM_LANES_NO_CLONES
#endif
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__)) && \
    !defined(IFEM_LANES_NO_CLONES)
#define IFEM_HOST_CLONES \
  __attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
#else
#define IFEM_HOST_CLONES
#endif

namespace ifem::solvers::lanes {

/// Lanes<C>::V: C doubles as one vector value (C = 8, 4, 2) or a double (C = 1).
template <int C>
struct Lanes;
template <>
struct Lanes<8> {
  typedef double V __attribute__((vector_size(64)));
};
template <>
struct Lanes<4> {
  typedef double V __attribute__((vector_size(32)));
};
template <>
struct Lanes<2> {
  typedef double V __attribute__((vector_size(16)));
};
template <>
struct Lanes<1> {
  typedef double V;
};

/// FloatLanes<C>::F: C floats as one vector (C ≥ 2).
template <int C>
struct FloatLanes {
  typedef float F __attribute__((vector_size(4 * C)));
};

/// UnsignedLanes<C>::U: C uint64 lanes (a scalar for C = 1).
template <int C>
struct UnsignedLanes {
  typedef std::uint64_t U __attribute__((vector_size(8 * C)));
};
template <>
struct UnsignedLanes<1> {
  typedef std::uint64_t U;
};

/// IntLanes<C>::I and ::U: C int64 and uint64 lanes, the bits of Lanes<C>::V (scalars for
/// C = 1). (GCC 12 ignored vector_size on a second attributed typedef in one class template,
/// hence UnsignedLanes.)
template <int C>
struct IntLanes {
  typedef std::int64_t I __attribute__((vector_size(8 * C)));
  typedef typename UnsignedLanes<C>::U U;
};
template <>
struct IntLanes<1> {
  typedef std::int64_t I;
  typedef std::uint64_t U;
};

/// The bits of v as a To of the same size (lanes reinterpreted, e.g. doubles as int64).
template <class To, class From>
[[gnu::always_inline]] inline To bit_cast(From v) {
  static_assert(sizeof(From) == sizeof(To));
  To t;
  std::memcpy(&t, &v, sizeof t);
  return t;
}

/// The C doubles at p (any alignment).
template <int C>
[[gnu::always_inline]] inline typename Lanes<C>::V load(const double* p) {
  typename Lanes<C>::V v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

/// Writes the C doubles of v at p (any alignment).
template <int C>
[[gnu::always_inline]] inline void store(double* p, typename Lanes<C>::V v) {
  std::memcpy(p, &v, sizeof v);
}

/// Whether the host runs AVX-512 F and VL (x86-64-v4's vectors; checked once). False off x86-64.
inline bool host_has_avx512() {
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
  static const bool has = __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl");
  return has;
#else
  return false;
#endif
}

/// Asks for the cache lines of n doubles from p, to be read (Write = false) or written soon
/// (__builtin_prefetch: a hint, no fault on any address). For rows of a row-major block whose
/// reads go all over it.
template <bool Write = false>
[[gnu::always_inline]] inline void prefetch(const double* p, std::int64_t n) {
  for (std::int64_t j = 0; j < n; j += 8) __builtin_prefetch(p + j, Write ? 1 : 0);
}

}  // namespace ifem::solvers::lanes
