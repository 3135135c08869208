#pragma once
// What the machine gives this process: cores (affinity, cgroup CPU quota) and memory
// (RLIMIT_AS, cgroup memory.max, MemAvailable), and the memory a drape is estimated to need.
#include <cstdint>
#include <string>

namespace woven::sim {

/// Cores this process may run on: the CPUs of its affinity mask (sched_getaffinity), capped by
/// a cgroup v2 CPU quota (cpu.max) when one is set; at least 1.
int available_cores();

/// The threads a run uses for a request (0: all available cores): min(request, available).
int threads_to_use(int requested);

/// The tightest lasting memory limit on this process, in bytes, and where it comes from: the
/// address-space limit, the cgroup's memory.max or the machine's memory (MemTotal).
struct MemoryLimit {
    double bytes = 0;  ///< 0: no limit found
    std::string what;  ///< "RLIMIT_AS", "cgroup memory.max", "the machine's memory (MemTotal)"
    bool virtual_memory = false;  ///< true for RLIMIT_AS (address space, not resident memory)
};
MemoryLimit memory_limit();

/// The memory free for use now (MemAvailable), bytes; 0 when unknown. It changes from moment
/// to moment: a run above it is a runtime failure ("not enough memory now"), not bad input.
double memory_available();

/// Estimated peak memory (bytes) of a drape of `particles` particles with `threads` threads:
/// resident (RSS) memory, and the address space (which RLIMIT_AS limits). Fitted to peak RSS
/// measured with /usr/bin/time -v (docs/RELIABILITY.md): 51x51 37 MB, 101x101 121 MB,
/// 151x151 278 MB, i.e. a + b n log2(n) (sparse Cholesky fill of a 2-D grid).
struct MemoryEstimate {
    double resident_bytes = 0;
    double address_space_bytes = 0;
};
MemoryEstimate estimate_drape_memory(long long particles, int threads);

/// The same form for a solve fitted elsewhere (testers' static solves): resident memory
/// kMargin (rss_base + rss_per_n_log_n n log2(n)), address space that plus the libraries' and
/// `threads` threads' share.
MemoryEstimate estimate_solve_memory(long long particles, double rss_base, double rss_per_n_log_n, int threads);

}  // namespace woven::sim
