#pragma once

/// Whether this test executable (and so the CLI it runs: the whole tree is built with the
/// same sanitizers) runs under AddressSanitizer. ASan reserves terabytes of address space
/// for its shadow memory, so a child run under `ulimit -v` aborts at start-up; tests bound
/// the child's memory with ASan's own hard_rss_limit_mb there instead (MemoryLimitPrefix).

#include <string>

namespace deploysim::testing {

#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kAddressSanitizer = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
inline constexpr bool kAddressSanitizer = true;
#else
inline constexpr bool kAddressSanitizer = false;
#endif
#else
inline constexpr bool kAddressSanitizer = false;
#endif

/// A shell prefix that bounds the memory of the next command to `mib` MiB: `ulimit -v`
/// (address space), or under ASan its hard RSS limit (the child then dies if it exceeds it).
inline std::string MemoryLimitPrefix(long mib) {
  if (kAddressSanitizer) {
    return "export ASAN_OPTIONS=\"${ASAN_OPTIONS:+$ASAN_OPTIONS:}hard_rss_limit_mb=" +
           std::to_string(mib) + "\"; ";
  }
  return "ulimit -v " + std::to_string(mib * 1024) + "; ";
}

}  // namespace deploysim::testing
