// The shard a process runs (sweep.hpp): --shard, or a launcher's ranks (Open MPI, PMI, a Slurm
// array) from the environment.
#include <cstdlib>
#include <functional>
#include <optional>
#include <string>

#include "woven/app/files.hpp"
#include "woven/batch/sweep.hpp"
#include "woven/batch/sweep_parts.hpp"
#include "woven/common/error.hpp"

namespace woven::batch {

using namespace woven::app;

ShardSpec shard_from(const std::optional<std::string>& option, const std::function<const char*(const char*)>& env)
{
    ShardSpec s;
    // "environment: <VARIABLE>: expected an integer in [lo, 1000000000], got 'x'"
    const auto number = [](const char* text, const std::string& what, long long lo) {
        try {
            return integer_from_text(text ? std::string(text) : std::string(), what, lo, 1'000'000'000);
        } catch (const InputError& e) {
            const std::string m = e.what();
            throw InputError("environment", what.substr(what.find(": ") + 2), m.substr(m.find("expected")));
        }
    };
    if (option) {
        const auto slash = option->find('/');
        const std::string expected = "expected I/N with 0 <= I < N (shard I of N, counted from 0), got '" + *option + "'";
        if (slash == std::string::npos) throw InputError(kCommandLine, "--shard", expected);
        try {
            s.index = static_cast<int>(integer_from_text(option->substr(0, slash), "--shard", 0, 1'000'000'000));
            s.count = static_cast<int>(integer_from_text(option->substr(slash + 1), "--shard", 1, 1'000'000'000));
        } catch (const InputError&) {
            throw InputError(kCommandLine, "--shard", expected);
        }
        if (s.index >= s.count) throw InputError(kCommandLine, "--shard", expected);
        s.source = "--shard";
        return s;
    }
    const auto from_env = [&](const char* rank, const char* size, const char* name) {
        const char* r = env(rank);
        const char* n = env(size);
        if (!r || !n) return false;
        const int index = static_cast<int>(number(r, std::string("environment: ") + rank, 0));
        const int count = static_cast<int>(number(n, std::string("environment: ") + size, 1));
        // A world of one (srun's PMI inside a Slurm array task) leaves the split to the next source.
        if (count == 1 && index == 0) return false;
        s.index = index;
        s.count = count;
        if (s.index >= s.count)
            throw InputError("environment", rank, "expected a rank below " + std::string(size) + " (" + n + "), got " + r);
        s.source = name;
        return true;
    };
    if (from_env("OMPI_COMM_WORLD_RANK", "OMPI_COMM_WORLD_SIZE", "Open MPI")) return s;
    if (from_env("PMI_RANK", "PMI_SIZE", "PMI")) return s;
    if (const char* id = env("SLURM_ARRAY_TASK_ID"); id && env("SLURM_ARRAY_TASK_COUNT")) {
        // Task ids run from SLURM_ARRAY_TASK_MIN in steps of SLURM_ARRAY_TASK_STEP (--array=0-7 or 1-8).
        const long long task = number(id, "environment: SLURM_ARRAY_TASK_ID", 0);
        const long long count = number(env("SLURM_ARRAY_TASK_COUNT"), "environment: SLURM_ARRAY_TASK_COUNT", 1);
        const long long min = env("SLURM_ARRAY_TASK_MIN") ? number(env("SLURM_ARRAY_TASK_MIN"), "environment: SLURM_ARRAY_TASK_MIN", 0) : 0;
        const long long step = env("SLURM_ARRAY_TASK_STEP") ? number(env("SLURM_ARRAY_TASK_STEP"), "environment: SLURM_ARRAY_TASK_STEP", 1) : 1;
        const long long index = (task - min) / step;
        if (task < min || (task - min) % step != 0 || index >= count)
            throw InputError("environment", "SLURM_ARRAY_TASK_ID",
                             "expected a task of the array (min " + std::to_string(min) + ", step " + std::to_string(step) + ", count " +
                                 std::to_string(count) + "), got " + id);
        s.index = static_cast<int>(index);
        s.count = static_cast<int>(count);
        s.source = "Slurm array";
        return s;
    }
    return s;
}

bool in_shard(std::size_t point_index, const ShardSpec& s)
{
    return static_cast<int>(point_index % static_cast<std::size_t>(s.count)) == s.index;
}

int local_ranks()
{
    for (const char* v : {"OMPI_COMM_WORLD_LOCAL_SIZE", "MPI_LOCALNRANKS"})
        if (const char* t = std::getenv(v)) {
            const long n = std::strtol(t, nullptr, 10);
            if (n >= 1 && n <= 4096) return static_cast<int>(n);
        }
    return 1;
}

}  // namespace woven::batch
