#include "woven/sim/resources.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include <sched.h>
#include <sys/resource.h>

namespace woven::sim {

namespace {

/// Fits of the measured peak RSS of `woven drape cube --grid N --threads T --max-steps 2`,
/// RSS = base + per_particle_log * n log2(n), relative least squares through N = 51, 101, 151,
/// 201, 251 (each within 3 %; docs/RELIABILITY.md). Two threads or more factorise the two sides of
/// the Newton matrix's top separator at once (sim/split_cholesky.hpp), each with its own copy of
/// the separator's dense block and CHOLMOD workspace: 8-13 % more.
constexpr double kRssBaseBytes = 15.8e6;
constexpr double kRssPerParticleLogBytes = 617;
constexpr double kRssBaseBytesThreaded = 16.9e6;
constexpr double kRssPerParticleLogBytesThreaded = 682;
/// Address space beyond RSS (VmPeak - VmHWM, measured 357 MB at 51x51 and 151x151 with one
/// thread: libraries, the heap arenas and stacks of the worker threads), plus per thread.
constexpr double kAddressSpaceBaseBytes = 400e6;
constexpr double kAddressSpacePerThreadBytes = 72e6;  ///< a glibc malloc arena (64 MiB) and a stack (8 MiB)
/// Margin on the estimate before comparing it with a limit.
constexpr double kMargin = 1.25;

/// The process's cgroup v2 folder ("/sys/fs/cgroup/<path>"), or "" when not on cgroup v2.
std::string cgroup_dir()
{
    std::ifstream in("/proc/self/cgroup");
    std::string line;
    while (std::getline(in, line))
        if (line.rfind("0::", 0) == 0) return "/sys/fs/cgroup" + line.substr(3);
    return "";
}

/// Reads the first line of a cgroup file, walking up from the process's cgroup to the root
/// (the tightest limit of the hierarchy is the one that applies; the first set one is taken).
std::string cgroup_value(const std::string& file)
{
    std::string dir = cgroup_dir();
    while (!dir.empty()) {
        std::ifstream in(dir + "/" + file);
        std::string v;
        if (in && std::getline(in, v) && !v.empty() && v.rfind("max", 0) != 0) return v;
        if (dir == "/sys/fs/cgroup") break;
        dir = dir.substr(0, dir.find_last_of('/'));
    }
    return "";
}

/// A /proc/meminfo value ("MemTotal:", "MemAvailable:") in bytes; 0 when not found.
double meminfo_bytes(const std::string& field)
{
    std::ifstream mem("/proc/meminfo");
    std::string key, unit;
    double kb = 0;
    while (mem >> key >> kb >> unit)
        if (key == field) return kb * 1024;
    return 0;
}

}  // namespace

int available_cores()
{
    int cores = 0;
    cpu_set_t set;
    CPU_ZERO(&set);
    if (sched_getaffinity(0, sizeof set, &set) == 0) cores = CPU_COUNT(&set);
    if (cores <= 0) cores = 1;
    // cpu.max: "<quota> <period>" (microseconds) or "max <period>".
    std::istringstream q(cgroup_value("cpu.max"));
    double quota = 0, period = 0;
    if (q >> quota >> period && quota > 0 && period > 0)
        cores = std::min(cores, std::max(1, static_cast<int>(std::ceil(quota / period))));
    return cores;
}

int threads_to_use(int requested)
{
    const int cores = available_cores();
    return requested <= 0 ? cores : std::min(requested, cores);
}

MemoryLimit memory_limit()
{
    MemoryLimit best;
    auto consider = [&](double bytes, const std::string& what, bool virt) {
        if (bytes > 0 && (best.bytes == 0 || bytes < best.bytes)) best = {bytes, what, virt};
    };
    rlimit rl{};
    if (getrlimit(RLIMIT_AS, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY) consider(double(rl.rlim_cur), "RLIMIT_AS", true);
    const std::string cg = cgroup_value("memory.max");
    if (!cg.empty()) consider(std::strtod(cg.c_str(), nullptr), "cgroup memory.max", false);
    consider(meminfo_bytes("MemTotal:"), "the machine's memory (MemTotal)", false);
    return best;
}

double memory_available() { return meminfo_bytes("MemAvailable:"); }

MemoryEstimate estimate_solve_memory(long long particles, double rss_base, double rss_per_n_log_n, int threads)
{
    const double n = static_cast<double>(std::max(particles, 2LL));
    MemoryEstimate e;
    e.resident_bytes = kMargin * (rss_base + rss_per_n_log_n * n * std::log2(n));
    e.address_space_bytes = e.resident_bytes + kAddressSpaceBaseBytes + kAddressSpacePerThreadBytes * std::max(threads, 1);
    return e;
}

MemoryEstimate estimate_drape_memory(long long particles, int threads)
{
    const bool threaded = threads >= 2;
    return estimate_solve_memory(particles, threaded ? kRssBaseBytesThreaded : kRssBaseBytes,
                                 threaded ? kRssPerParticleLogBytesThreaded : kRssPerParticleLogBytes, threads);
}

}  // namespace woven::sim
