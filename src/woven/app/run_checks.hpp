#pragma once
// Checks a run makes before its work: threads it can use, memory it will need, an output
// directory it can write, an error of the fitting stage naming the fabric's file (no non-finite
// number in its outputs: io/output_checks.hpp).
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "woven/sim/resources.hpp"
#include "woven/common/types.hpp"

namespace woven::app {

/// Threads asked for (0: all) and used: min(asked, sim::available_cores()); a request above the
/// cores available adds a warning to `warnings` (more threads than cores only slows a run down).
struct ThreadCount {
    int requested = 0;
    int used = 1;
};
ThreadCount choose_threads(int requested, std::vector<std::string>& warnings);

/// Refuses (InputError "<source>: <field>: ... needs about X GB ..., more than the Y GB of
/// <limit>") a drape whose estimated memory exceeds the process's limit. Returns the estimate
/// it checked (sim::estimate_drape_memory), for a report to state.
sim::MemoryEstimate check_memory(long long particles, int threads, const std::string& source, const std::string& field);
/// The same check for a memory estimate made elsewhere (kes-test's specimens); `advice` ends
/// the message ("use a larger --sigma-cm").
void check_memory_estimate(const sim::MemoryEstimate& estimate, long long particles, const std::string& source,
                           const std::string& field, const std::string& advice);
/// The check itself, against a lasting `limit` (RLIMIT_AS, cgroup, the machine's memory:
/// InputError above it, exit 2) and the memory `available` now (0: unknown; RuntimeError "not
/// enough memory now" above it, exit 1).
void check_memory_estimate(const sim::MemoryEstimate& estimate, const sim::MemoryLimit& limit, double available, long long particles,
                           const std::string& source, const std::string& field, const std::string& advice);

/// Each `dir`/name that exists must be a regular file (bad usage otherwise: InputError
/// "command line: --out: <path> exists and is not a regular file").
void check_output_targets(const std::string& dir, const std::vector<std::string>& names);

/// Runs `fit` (which fits a fabric's curves); an InputError that names the fabric rather than a
/// file ("fabric 'probe': ...") is rethrown naming `fabric_source` (its file, or "built-in
/// fabric 'x'").
void with_fabric_source(const std::string& fabric_source, const std::function<void()>& fit);

/// The name a fabric's errors carry: the path for a fabric file, "built-in fabric 'x'" else.
std::string fabric_source(const std::string& name_or_path);

}  // namespace woven::app
