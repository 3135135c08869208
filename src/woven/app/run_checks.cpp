#include "woven/app/run_checks.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>

#include "woven/app/files.hpp"
#include "woven/sim/resources.hpp"
#include "woven/common/error.hpp"

namespace woven::app {

namespace {

std::string gb(double bytes)
{
    char b[32];
    std::snprintf(b, sizeof b, "%.3g GB", bytes / 1e9);
    return b;
}

}  // namespace

ThreadCount choose_threads(int requested, std::vector<std::string>& warnings)
{
    ThreadCount t;
    t.requested = requested;
    t.used = sim::threads_to_use(requested);
    if (requested > t.used)
        warnings.push_back(std::to_string(requested) + " threads asked for, " + std::to_string(t.used) +
                           " cores available to this process; using " + std::to_string(t.used));
    return t;
}

sim::MemoryEstimate check_memory(long long particles, int threads, const std::string& source, const std::string& field)
{
    const sim::MemoryEstimate e = sim::estimate_drape_memory(particles, threads);
    check_memory_estimate(e, particles, source, field, "use a smaller grid");
    return e;
}

void check_memory_estimate(const sim::MemoryEstimate& e, long long particles, const std::string& source, const std::string& field,
                           const std::string& advice)
{
    check_memory_estimate(e, sim::memory_limit(), sim::memory_available(), particles, source, field, advice);
}

void check_memory_estimate(const sim::MemoryEstimate& e, const sim::MemoryLimit& limit, double available, long long particles,
                           const std::string& source, const std::string& field, const std::string& advice)
{
    if (limit.bytes > 0) {
        const double need = limit.virtual_memory ? e.address_space_bytes : e.resident_bytes;
        if (need > limit.bytes)
            throw InputError(source, field,
                             std::to_string(particles) + " particles need about " + gb(need) +
                                 (limit.virtual_memory ? " of address space" : "") + " (estimate), more than the " +
                                 gb(limit.bytes) + " of " + limit.what + "; " + advice);
    }
    // Within the lasting limits but above what is free at this moment: a runtime failure.
    if (available > 0 && e.resident_bytes > available)
        throw RuntimeError("not enough memory now: " + std::to_string(particles) + " particles need about " + gb(e.resident_bytes) +
                           " (estimate), " + gb(available) + " is available (MemAvailable); run again when memory is free");
}

void check_output_targets(const std::string& dir, const std::vector<std::string>& names)
{
    namespace fs = std::filesystem;
    for (const auto& n : names) {
        const fs::path p = fs::path(dir) / n;
        std::error_code ec;
        const auto st = fs::symlink_status(p, ec);
        if (!ec && fs::exists(st) && !fs::is_regular_file(st))
            throw InputError(kCommandLine, "--out", p.string() + " exists and is not a regular file");
    }
}

std::string fabric_source(const std::string& name_or_path)
{
    const bool path = name_or_path.find('/') != std::string::npos || name_or_path.ends_with(".toml");
    return path ? name_or_path : "built-in fabric '" + name_or_path + "'";
}

void with_fabric_source(const std::string& source, const std::function<void()>& fit)
{
    try {
        fit();
    } catch (const InputError& e) {
        if (e.source().rfind("fabric '", 0) != 0 || e.source() == source) throw;
        const std::string what = e.what();
        std::string expected = what.substr(std::min(what.size(), e.source().size() + 2));
        if (!e.field().empty() && expected.rfind(e.field() + ": ", 0) == 0) expected = expected.substr(e.field().size() + 2);
        throw InputError(source, e.field(), expected);
    }
}

}  // namespace woven::app
