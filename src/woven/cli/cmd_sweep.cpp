// woven sweep PLAN.toml: runs the points of a plan (io/sweep_plan.hpp, docs/SWEEP-FORMAT.md),
// each as a child process of this binary running the plan's command (drape, cusick, kes-test)
// into a private work folder; a point that finishes and verifies is renamed into place as
// <sweep>/<point name>/, so a point's folder is there complete (its manifest, every file's
// SHA-256, point.json) or not at all. Resume is the default: a point whose folder verifies with
// the plan's command line is not run again. --jobs J runs J points at once; the points are
// split between the ranks of a launcher (Open MPI, PMI, a Slurm array) or --shard I/N, every
// rank writing into the shared folder and merging (sweep.csv, sweep.json) at its end under a
// lock on the folder; --merge merges alone, idempotently.
#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <fcntl.h>
#include <sys/file.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "woven/cli/args.hpp"
#include "woven/cli/commands.hpp"
#include "woven/cli/resources.hpp"
#include "woven/cli/run_checks.hpp"
#include "woven/cli/progress.hpp"
#include "woven/cli/sweep.hpp"
#include "woven/common/error.hpp"
#include "woven/io/fabric_file.hpp"
#include "woven/io/output_file.hpp"
#include "woven/io/scene_file.hpp"
#include "woven/io/sweep_plan.hpp"

namespace woven::cli {

namespace fs = std::filesystem;

namespace {

struct SweepOptions {
    std::string plan;
    std::optional<std::string> out;
    std::string jobs = "1";
    std::optional<std::string> shard;
    bool merge = false;
    bool list = false;
};

/// The sweep's own signal: the first SIGINT/SIGTERM stops the children (SIGTERM) and exits
/// 128 + signal once they are gone; their work folders are removed.
std::atomic<int> g_sweep_signal{0};

extern "C" void on_sweep_signal(int sig)
{
    int none = 0;
    g_sweep_signal.compare_exchange_strong(none, sig);
}

std::string host_name()
{
    char h[256] = {};
    if (::gethostname(h, sizeof h - 1) != 0 || h[0] == 0) return "host";
    std::string s = h;
    for (char& c : s)
        if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '-')) c = '-';
    return s;
}

/// Writes `text` to `path` through a unique temporary in the same folder and a rename.
void write_atomic(const fs::path& path, const std::string& text)
{
    static std::atomic<int> counter{0};
    const fs::path tmp = path.parent_path() / (".woven-tmp." + std::to_string(::getpid()) + "." + std::to_string(counter++) + "." +
                                               path.filename().string());
    {
        std::ofstream out(tmp, std::ios::binary);
        out << text;
        out.flush();
        if (!out) throw RuntimeError(path.string() + ": cannot write: " + std::strerror(errno));
    }
    std::error_code ec;
    fs::rename(tmp, path, ec);
    if (ec) {
        fs::remove(tmp, ec);
        throw RuntimeError(path.string() + ": cannot move into place: " + ec.message());
    }
}

/// What the plan asks of a point, as point.json records it: a finished folder is this point's
/// only when these match.
nlohmann::json point_signature(const io::SweepPoint& p)
{
    nlohmann::json s;
    s["args"] = p.args;
    nlohmann::json so = nlohmann::json::object(), fo = nlohmann::json::object();
    for (const auto& o : p.scene_overrides) so[o.key] = o.text;
    for (const auto& o : p.fabric_overrides) fo[o.key] = o.text;
    s["scene_overrides"] = so;
    s["fabric_overrides"] = fo;
    return s;
}


/// A JSON file of the sweep folder (point.json, a manifest, a failure record), read as
/// io::read_output_json reads it; nullopt (and the reason in `why`) when it cannot be.
std::optional<nlohmann::json> read_json(const fs::path& p, std::string* why = nullptr)
{
    try {
        return io::read_output_json(p.string(), io::kMaxManifestBytes, "a file woven sweep wrote");
    } catch (const InputError& e) {
        if (why) *why = e.what();
        return std::nullopt;
    }
}

std::optional<nlohmann::json> read_manifest(const fs::path& dir)
{
    for (const char* m : kManifests)
        if (fs::exists(dir / m)) return read_json(dir / m);
    return std::nullopt;
}

/// A value as JSON: a number as a number (integers as integers), else the text.
nlohmann::json value_json(const io::SweepValue& v)
{
    if (!v.number) return v.text;
    if (v.text.find_first_of(".eEn") == std::string::npos) return std::stoll(v.text);
    return std::stod(v.text);
}

/// The merged table's output columns in a reading order (others follow, sorted).
const std::vector<std::string>& preferred_columns()
{
    static const std::vector<std::string> c = {"drape_coefficient_percent", "drape_coefficient_std", "nodes", "energy_J", "folds",
                                               "projected_area_m2", "max_residual_rel", "converged", "steps", "iterations",
                                               "particles", "tests", "worst_summary_rel_error", "worst_curve_rel_error"};
    return c;
}

}  // namespace

ShardSpec shard_from(const std::optional<std::string>& option, const std::function<const char*(const char*)>& env)
{
    ShardSpec s;
    // "environment: <VARIABLE>: expected an integer in [lo, 1000000000], got 'x'"
    const auto number = [](const char* text, const std::string& what, long long lo) {
        try {
            return parse_integer(text ? std::string(text) : std::string(), what, lo, 1'000'000'000);
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
            s.index = static_cast<int>(parse_integer(option->substr(0, slash), "--shard", 0, 1'000'000'000));
            s.count = static_cast<int>(parse_integer(option->substr(slash + 1), "--shard", 1, 1'000'000'000));
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

SweepFolderLock::SweepFolderLock(const std::string& dir)
{
    fd_ = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd_ < 0) throw RuntimeError(dir + ": cannot open the sweep folder: " + std::strerror(errno));
    while (::flock(fd_, LOCK_EX) != 0)
        if (errno != EINTR) {
            ::close(fd_);
            throw RuntimeError(dir + ": cannot lock the sweep folder: " + std::strerror(errno));
        }
}

SweepFolderLock::~SweepFolderLock() { ::close(fd_); }

namespace {

/// The launcher's ranks on this node, which share its cores (1 when none is known).
int local_ranks()
{
    for (const char* v : {"OMPI_COMM_WORLD_LOCAL_SIZE", "MPI_LOCALNRANKS"})
        if (const char* t = std::getenv(v)) {
            const long n = std::strtol(t, nullptr, 10);
            if (n >= 1 && n <= 4096) return static_cast<int>(n);
        }
    return 1;
}

/// `s` as one shell word: unchanged when it holds only [A-Za-z0-9_./=:,+@%-], else in single quotes.
std::string shell_quote(const std::string& s)
{
    const bool plain = !s.empty() && std::all_of(s.begin(), s.end(), [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) || std::strchr("_./=:,+@%-", c) != nullptr;
    });
    if (plain) return s;
    std::string q = "'";
    for (const char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

/// The sweep's own folders (.work, failed) are made here, never followed: a symlink planted in
/// their place (which would send failure records or work folders elsewhere) is bad usage.
void require_own_folders(const fs::path& sweep)
{
    for (const char* name : {".work", "failed"}) {
        const fs::path p = sweep / name;
        std::error_code ec;
        const auto st = fs::symlink_status(p, ec);
        if (fs::is_symlink(st))
            throw InputError(kCommandLine, "--out", p.string() + " is a symbolic link; expected the sweep's own folder (remove the link)");
        if (fs::exists(st) && !fs::is_directory(st))
            throw InputError(kCommandLine, "--out", p.string() + " exists and is not a directory");
    }
}

/// A point's status in the sweep folder.
struct PointState {
    bool done = false;
    std::string problem;  ///< why a folder that is there does not count ("" when absent)
};

PointState point_state(const fs::path& sweep, const io::SweepPoint& p)
{
    PointState st;
    const fs::path dir = sweep / p.name;
    std::error_code ec;
    if (fs::is_symlink(fs::symlink_status(dir, ec))) {
        st.problem = dir.string() + ": a symbolic link, not a folder this sweep wrote";
        return st;
    }
    if (!fs::is_directory(dir, ec)) return st;
    const auto problems = check_output_folder(dir.string());
    if (!problems.empty()) {
        st.problem = problems.front();
        return st;
    }
    std::string why;
    const auto pj = read_json(dir / "point.json", &why);
    if (!pj || !pj->is_object() || !pj->contains("plan")) {
        st.problem = why.empty() ? (dir / "point.json").string() + ": missing or unreadable" : why;
        return st;
    }
    if ((*pj)["plan"] != point_signature(p)) {
        st.problem = (dir / "point.json").string() + ": ran another command line than the plan's (the plan changed)";
        return st;
    }
    st.done = true;
    return st;
}

/// A point that is running: its child and work folder.
struct Running {
    pid_t pid = -1;
    io::SweepPoint point;
    fs::path work;
    std::chrono::steady_clock::time_point start;
    std::vector<std::string> args;
};

/// The last `lines` lines of a file (a failed point's log).
std::string tail_lines(const fs::path& p, int lines)
{
    const auto t = read_output_file(p.string());
    if (!t) return {};
    std::size_t at = t->size();
    for (int k = 0; k <= lines && at > 0; ++k) {
        const auto nl = t->rfind('\n', at - 1);
        if (nl == std::string::npos) {
            at = 0;
            break;
        }
        at = nl;
        if (k == lines) ++at;
    }
    return t->substr(at);
}

/// The value of a point's own --threads, if its command line has one.
std::optional<std::string> plan_threads(const std::vector<std::string>& args)
{
    for (std::size_t k = 0; k + 1 < args.size(); ++k)
        if (args[k] == "--threads") return args[k + 1];
    return std::nullopt;
}

/// "N thread(s)" each point runs on: the plan's --threads where its points give one (0: all
/// cores), else the share of the cores the sweep passes. Read from the first 1000 points to run
/// (points are made on demand; a plan's threads are an option or an axis).
std::string threads_text(const io::SweepPlan& plan, const std::vector<std::size_t>& todo, int share)
{
    std::optional<std::string> given;
    bool some_given = false, some_not = false, differ = false;
    for (std::size_t k = 0; k < todo.size() && k < 1000; ++k) {
        const auto t = plan_threads(plan.point(todo[k]).args);
        (t ? some_given : some_not) = true;
        if (t && given && *t != *given) differ = true;
        if (t && !given) given = t;
    }
    const auto count = [](const std::string& n) { return n + (n == "1" ? " thread" : " threads"); };
    if (!some_given) return count(std::to_string(share));
    if (differ || some_not) return "the plan's --threads (or " + count(std::to_string(share)) + ")";
    return *given == "0" ? "all cores (the plan's --threads 0)" : count(*given) + " (the plan's --threads)";
}

class SweepRunner {
public:
    SweepRunner(const io::SweepPlan& plan, fs::path sweep, int jobs, int threads_per_point,
                std::function<void(const io::SweepPoint&)> on_start = {})
        : plan_(plan), sweep_(std::move(sweep)), work_root_(sweep_ / ".work"), jobs_(jobs), threads_(threads_per_point),
          host_(host_name()), on_start_(std::move(on_start))
    {
    }

    /// Runs the points of the plan numbered `todo`; returns the number that failed.
    int run(const std::vector<std::size_t>& todo)
    {
        fs::create_directories(work_root_);
        fs::create_directories(sweep_ / "failed");
        remove_stale_work();
        std::size_t next = 0, finished = 0;
        std::vector<Running> running;
        while (next < todo.size() || !running.empty()) {
            if (g_sweep_signal.load() != 0) {
                stop(running);
                return failed_;
            }
            while (next < todo.size() && static_cast<int>(running.size()) < jobs_) running.push_back(start(plan_.point(todo[next++])));
            int status = 0;
            const pid_t pid = ::waitpid(-1, &status, WNOHANG);
            if (pid <= 0) {
                std::this_thread::sleep_for(std::chrono::milliseconds(50));
                continue;
            }
            const auto it = std::find_if(running.begin(), running.end(), [&](const Running& r) { return r.pid == pid; });
            if (it == running.end()) continue;
            Running r = *it;
            running.erase(it);
            ++finished;
            finish(r, status, finished, todo.size());
        }
        return failed_;
    }

    int ran() const { return ran_; }

private:
    /// Work folders "<name>.<host>.<pid>" of this host whose process is gone.
    void remove_stale_work()
    {
        std::error_code ec;
        for (fs::directory_iterator it(work_root_, ec), end; !ec && it != end; it.increment(ec)) {
            const std::string n = it->path().filename().string();
            const auto dot = n.rfind('.');
            if (dot == std::string::npos) continue;
            const auto dot2 = n.rfind('.', dot - 1);
            if (dot2 == std::string::npos || n.substr(dot2 + 1, dot - dot2 - 1) != host_) continue;
            const long pid = std::strtol(n.c_str() + dot + 1, nullptr, 10);
            if (pid <= 0 || pid == ::getpid() || ::kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH) continue;
            std::error_code rm;
            fs::remove_all(it->path(), rm);
        }
    }

    /// The point's scene or fabric with its overrides, written into its work folder.
    std::vector<std::string> command_line(const io::SweepPoint& p, const fs::path& work)
    {
        std::vector<std::string> args = p.args;
        if (!p.scene_overrides.empty()) {
            const std::string scene = args[1];
            const std::string text = io::scene_or_fabric_text(scene, "scene");
            const fs::path file = work / "scene.toml";
            std::ofstream(file) << io::apply_toml_overrides(text, scene, p.scene_overrides);
            args[1] = file.string();
            // A built-in scene names its fabric by name; a scene file's relative paths would move
            // with it: the plan's documentation asks for absolute ones in overridden scene files.
        }
        if (!p.fabric_overrides.empty()) {
            std::string fabric;
            std::size_t at = 0;
            if (plan_.command == "drape") {
                for (std::size_t k = 2; k + 1 < args.size(); ++k)
                    if (args[k] == "--fabric") at = k + 1;
                if (at == 0) {
                    fabric = io::find_scene(args[1]).fabric;
                    args.push_back("--fabric");
                    args.push_back("");
                    at = args.size() - 1;
                } else {
                    fabric = args[at];
                }
            } else {
                at = 1;
                fabric = args[1];
            }
            const std::string text = io::scene_or_fabric_text(fabric, "fabric");
            const fs::path file = work / "fabric.toml";
            std::ofstream(file) << io::apply_toml_overrides(text, fabric, p.fabric_overrides);
            args[at] = file.string();
        }
        if (!plan_threads(args)) {
            args.push_back("--threads");
            args.push_back(std::to_string(threads_));
        }
        args.push_back("--out");
        args.push_back(work.string());
        return args;
    }

    Running start(io::SweepPoint point)
    {
        Running r;
        r.point = std::move(point);
        const io::SweepPoint& p = r.point;
        r.work = work_root_ / (p.name + "." + host_ + "." + std::to_string(::getpid()));
        std::error_code ec;
        fs::remove_all(r.work, ec);
        fs::create_directories(r.work);
        r.args = command_line(p, r.work);
        const std::string log = (r.work / "log.txt").string();
        std::vector<char*> argv;
        static const std::string self = "/proc/self/exe";
        std::string argv0 = "woven";
        argv.push_back(argv0.data());
        for (auto& a : r.args) argv.push_back(a.data());
        argv.push_back(nullptr);
        const pid_t parent = ::getpid();
        r.start = std::chrono::steady_clock::now();
        const pid_t pid = ::fork();
        if (pid < 0) throw RuntimeError(std::string("cannot start a point: fork: ") + std::strerror(errno));
        if (pid == 0) {
            // The child dies with the sweep (a SIGKILL of a rank leaves no point running).
            ::prctl(PR_SET_PDEATHSIG, SIGKILL);
            if (::getppid() != parent) ::_exit(127);
            signal(SIGINT, SIG_DFL);
            signal(SIGTERM, SIG_DFL);
            const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
            if (fd >= 0) {
                ::dup2(fd, STDOUT_FILENO);
                ::dup2(fd, STDERR_FILENO);
            }
            ::execv(self.c_str(), argv.data());
            ::_exit(127);
        }
        r.pid = pid;
        if (on_start_) on_start_(p);
        return r;
    }

    void finish(const Running& r, int status, std::size_t finished, std::size_t total)
    {
        const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - r.start).count();
        const io::SweepPoint& p = r.point;
        const int code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
        std::ostringstream head;
        head << "[" << finished << "/" << total << "] " << p.name << ": ";
        if (g_sweep_signal.load() != 0 && code != 0) {  // stopped by this sweep: not a failure
            remove_work(r.work);
            return;
        }
        std::string problem;
        if (code != 0) {
            problem = "exit code " + std::to_string(code);
        } else {
            const auto problems = check_output_folder(r.work.string());
            if (!problems.empty()) problem = problems.front();
            const auto m = read_manifest(r.work);
            if (problem.empty() && m && m->value("interrupted", false)) problem = "interrupted";
        }
        if (!problem.empty()) {
            ++failed_;
            nlohmann::json f;
            f["point"] = p.name;
            f["plan"] = point_signature(p);
            f["exit_code"] = code;
            f["problem"] = problem;
            f["wall_time_s"] = wall;
            f["host"] = host_;
            f["pid"] = r.pid;
            f["log_tail"] = tail_lines(r.work / "log.txt", 8);
            write_atomic(sweep_ / "failed" / (p.name + ".json"), f.dump(2) + "\n");
            remove_work(r.work);
            std::cerr << head.str() << "FAILED (" << problem << ", " << std::fixed << std::setprecision(1) << wall << " s); see "
                      << (sweep_ / "failed" / (p.name + ".json")).string() << "\n"
                      << std::flush;
            std::cerr.unsetf(std::ios::fixed);
            return;
        }
        nlohmann::json pj;
        pj["point"] = p.name;
        pj["index"] = p.index;
        nlohmann::json values = nlohmann::json::object();
        for (const auto& v : p.values) values[v.key] = value_json(v);
        pj["values"] = values;
        pj["plan"] = point_signature(p);
        pj["command_line"] = r.args;
        pj["wall_time_s"] = wall;
        pj["host"] = host_;
        pj["pid"] = r.pid;
        pj["run_id"] = host_ + "." + std::to_string(::getpid()) + "." + std::to_string(r.pid);
        {
            std::ofstream out(r.work / "point.json");
            out << pj.dump(2) << "\n";
        }
        const fs::path target = sweep_ / p.name;
        if (::rename(r.work.c_str(), target.c_str()) != 0) {
            // Something is there: another writer's complete folder (keep it), or an incomplete or
            // stale one (moved aside, then replaced).
            const PointState there = point_state(sweep_, p);
            if (there.done) {
                remove_work(r.work);
                std::cerr << head.str() << "done elsewhere meanwhile; kept that folder\n" << std::flush;
                return;
            }
            const fs::path aside = work_root_ / ("replaced." + p.name + "." + host_ + "." + std::to_string(::getpid()));
            std::error_code ec;
            fs::remove_all(aside, ec);
            if (::rename(target.c_str(), aside.c_str()) != 0 || ::rename(r.work.c_str(), target.c_str()) != 0)
                throw RuntimeError(target.string() + ": cannot move the point's folder into place: " + std::strerror(errno));
            fs::remove_all(aside, ec);
        }
        std::error_code ec;
        fs::remove(sweep_ / "failed" / (p.name + ".json"), ec);
        ++ran_;
        std::cerr << head.str() << "ran in " << std::fixed << std::setprecision(1) << wall << " s\n" << std::flush;
        std::cerr.unsetf(std::ios::fixed);
    }

    void remove_work(const fs::path& w)
    {
        std::error_code ec;
        fs::remove_all(w, ec);
    }

    void stop(std::vector<Running>& running)
    {
        for (const auto& r : running) ::kill(r.pid, SIGTERM);
        for (const auto& r : running) {
            int status = 0;
            while (::waitpid(r.pid, &status, 0) < 0 && errno == EINTR) {
            }
            remove_work(r.work);
        }
        running.clear();
    }

    const io::SweepPlan& plan_;
    fs::path sweep_, work_root_;
    int jobs_, threads_;
    std::string host_;
    std::function<void(const io::SweepPoint&)> on_start_;
    int failed_ = 0, ran_ = 0;
};

std::string csv_cell(const nlohmann::json& v)
{
    if (v.is_null()) return "";
    std::string s = v.is_string() ? v.get<std::string>() : v.dump();
    if (s.find_first_of(",\"\n") != std::string::npos) {
        std::string q = "\"";
        for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
        return q + "\"";
    }
    return s;
}

}  // namespace

nlohmann::json point_outputs(const std::string& command, const nlohmann::json& m)
{
    nlohmann::json o = nlohmann::json::object();
    const auto get = [&](const nlohmann::json& j, std::initializer_list<const char*> path) -> nlohmann::json {
        const nlohmann::json* at = &j;
        for (const char* k : path) {
            if (!at->is_object() || !at->contains(k)) return nullptr;
            at = &(*at)[k];
        }
        return *at;
    };
    if (command == "drape") {
        o["energy_J"] = get(m, {"energy", "total_J"});
        o["max_residual_rel"] = get(m, {"equilibrium", "max_residual_rel"});
        o["converged"] = get(m, {"converged"});
        o["steps"] = get(m, {"steps"});
        o["iterations"] = get(m, {"iterations"});
        o["particles"] = get(m, {"particles"});
        // The fold structure: billows per corner and box face ("2+0 2+1 2+1 2+0"), the
        // corner analysis of the drape (analysis/folds.hpp) when the scene has a box.
        std::string folds;
        const auto corners = get(m, {"folds", "corners"});
        if (corners.is_array())
            for (const auto& c : corners) {
                std::string b;
                if (c.contains("billows") && c["billows"].is_array())
                    for (const auto& n : c["billows"]) b += (b.empty() ? "" : "+") + n.dump();
                folds += (folds.empty() ? "" : " ") + b;
            }
        o["folds"] = folds.empty() ? nlohmann::json(nullptr) : nlohmann::json(folds);
        o["projected_area_m2"] = get(m, {"folds", "projected_area_m2"});
    } else if (command == "cusick") {
        const bool many = m.contains("drape_coefficient_mean");
        o["drape_coefficient_percent"] = many ? m["drape_coefficient_mean"] : get(m, {"drape_coefficient_percent"});
        o["drape_coefficient_std"] = many ? m["drape_coefficient_std"] : nlohmann::json(0.0);
        std::string nodes;
        double energy = 0, residual = 0;
        long steps = 0;
        bool any = false;
        if (m.contains("runs") && m["runs"].is_array())
            for (const auto& r : m["runs"]) {
                nodes += (nodes.empty() ? "" : " ") + r.value("nodes", nlohmann::json(nullptr)).dump();
                energy += r.value("energy_J", 0.0) / static_cast<double>(m["runs"].size());
                residual = std::max(residual, r.value("max_residual_rel", 0.0));
                steps += r.value("steps", 0L);
                any = true;
            }
        o["nodes"] = nodes;
        o["energy_J"] = any ? nlohmann::json(energy) : nlohmann::json(nullptr);
        o["max_residual_rel"] = any ? nlohmann::json(residual) : nlohmann::json(nullptr);
        o["converged"] = get(m, {"converged"});
        o["steps"] = any ? nlohmann::json(steps) : nlohmann::json(nullptr);
        o["particles"] = get(m, {"particles"});
    } else {
        double worst_summary = 0, worst_curve = 0;
        int tests = 0;
        if (m.contains("tests") && m["tests"].is_array())
            for (const auto& t : m["tests"]) {
                ++tests;
                if (t.contains("summary_rel_error") && t["summary_rel_error"].is_number())
                    worst_summary = std::max(worst_summary, std::abs(t["summary_rel_error"].get<double>()));
                if (t.contains("curve_max_rel_error") && t["curve_max_rel_error"].is_number())
                    worst_curve = std::max(worst_curve, t["curve_max_rel_error"].get<double>());
                const std::string name = t.value("test", std::string("test")) + "_" + t.value("direction", std::string(""));
                o[name + "_simulated"] = t.value("simulated_summary", nlohmann::json(nullptr));
                o[name + "_input"] = t.value("input_summary", nlohmann::json(nullptr));
            }
        o["tests"] = tests;
        o["worst_summary_rel_error"] = worst_summary;
        o["worst_curve_rel_error"] = worst_curve;
    }
    return o;
}

MergeCounts merge_sweep(const io::SweepPlan& plan, const std::string& sweep_dir)
{
    const fs::path sweep(sweep_dir);
    const SweepFolderLock lock(sweep_dir);
    MergeCounts counts;
    nlohmann::json rows = nlohmann::json::array();
    std::vector<std::string> output_keys;
    for (std::size_t index = 0; index < plan.size(); ++index) {
        const io::SweepPoint p = plan.point(index);
        nlohmann::json row;
        row["point"] = p.name;
        row["index"] = p.index;
        nlohmann::json values = nlohmann::json::object();
        for (const auto& v : p.values) values[v.key] = value_json(v);
        row["values"] = values;
        const PointState st = point_state(sweep, p);
        if (st.done) {
            ++counts.done;
            const auto pj = read_json(sweep / p.name / "point.json");
            const auto m = read_manifest(sweep / p.name);
            row["status"] = "done";
            row["wall_time_s"] = (*pj)["wall_time_s"];
            row["host"] = pj->value("host", std::string());
            row["outputs"] = point_outputs(plan.command, m ? *m : nlohmann::json::object());
            for (auto it = row["outputs"].begin(); it != row["outputs"].end(); ++it)
                if (std::find(output_keys.begin(), output_keys.end(), it.key()) == output_keys.end()) output_keys.push_back(it.key());
        } else if (const auto f = read_json(sweep / "failed" / (p.name + ".json")); f && f->value("plan", nlohmann::json()) == point_signature(p)) {
            ++counts.failed;
            row["status"] = "failed";
            row["wall_time_s"] = f->value("wall_time_s", nlohmann::json(nullptr));
            row["problem"] = f->value("problem", std::string());
        } else {
            ++counts.missing;
            row["status"] = "missing";
            if (!st.problem.empty()) row["problem"] = st.problem;
        }
        rows.push_back(row);
    }
    nlohmann::json j;
    j["version"] = WOVEN_VERSION;
    j["plan"] = plan.source;
    j["name"] = plan.name;
    j["description"] = plan.description;
    j["command"] = plan.command;
    nlohmann::json axes = nlohmann::json::array();
    for (const auto& a : plan.axes) {
        nlohmann::json vals = nlohmann::json::array();
        for (const auto& v : a.values) vals.push_back(value_json(v));
        axes.push_back({{"key", a.key}, {"values", vals}});
    }
    j["axes"] = axes;
    j["points"] = plan.size();
    j["done"] = counts.done;
    j["failed"] = counts.failed;
    j["missing"] = counts.missing;
    j["rows"] = rows;
    std::vector<std::string> ordered;
    for (const auto& k : preferred_columns())
        if (std::find(output_keys.begin(), output_keys.end(), k) != output_keys.end()) ordered.push_back(k);
    std::sort(output_keys.begin(), output_keys.end());
    for (const auto& k : output_keys)
        if (std::find(ordered.begin(), ordered.end(), k) == ordered.end()) ordered.push_back(k);
    output_keys = ordered;
    j["output_columns"] = output_keys;
    std::ostringstream csv;
    csv << "point";
    for (const auto& a : plan.axes) csv << "," << csv_cell(a.key);
    csv << ",status,wall_time_s";
    for (const auto& k : output_keys) csv << "," << k;
    csv << "\n";
    for (const auto& r : rows) {
        csv << csv_cell(r["point"]);
        for (const auto& a : plan.axes) csv << "," << csv_cell(r["values"][a.key]);
        csv << "," << csv_cell(r["status"]) << "," << csv_cell(r.value("wall_time_s", nlohmann::json(nullptr)));
        for (const auto& k : output_keys) csv << "," << (r.contains("outputs") && r["outputs"].contains(k) ? csv_cell(r["outputs"][k]) : "");
        csv << "\n";
    }
    write_atomic(sweep / "sweep.json", j.dump(2) + "\n");
    write_atomic(sweep / "sweep.csv", csv.str());
    return counts;
}

/// Reads every point's overridden scene and fabric with the commands' own readers before
/// anything runs: a bad value or a key the file does not have (a warning when a scene is read)
/// is an error naming the plan and the point.
void validate_sweep_overrides(const io::SweepPlan& plan)
{
    bool any = false;
    for (const auto& a : plan.axes) any = any || a.key.rfind("scene.", 0) == 0 || a.key.rfind("fabric.", 0) == 0;
    for (const auto& v : plan.fixed) any = any || v.key.rfind("scene.", 0) == 0 || v.key.rfind("fabric.", 0) == 0;
    if (!any) return;
    std::set<std::string> seen;
    for (std::size_t index = 0; index < plan.size(); ++index) {
        const io::SweepPoint p = plan.point(index);
        if (p.scene_overrides.empty() && p.fabric_overrides.empty()) continue;
        const std::string key = point_signature(p).dump();
        if (!seen.insert(key).second) continue;
        std::vector<std::string> warnings;
        try {
            if (!p.scene_overrides.empty()) {
                const std::string text = io::apply_toml_overrides(io::scene_or_fabric_text(p.args[1], "scene"), p.args[1], p.scene_overrides);
                (void)io::parse_scene(text, "scene " + p.args[1], ".", &warnings);
            }
            if (!p.fabric_overrides.empty()) {
                std::string fabric;
                for (std::size_t k = 2; k + 1 < p.args.size(); ++k)
                    if (p.args[k] == "--fabric") fabric = p.args[k + 1];
                if (plan.command != "drape") fabric = p.args[1];
                if (fabric.empty()) fabric = io::find_scene(p.args[1]).fabric;
                const std::string text = io::apply_toml_overrides(io::scene_or_fabric_text(fabric, "fabric"), fabric, p.fabric_overrides);
                (void)io::parse_fabric(text, "fabric " + fabric, &warnings);
            }
        } catch (const InputError& e) {
            throw InputError(plan.source, "point " + p.name, e.what());
        }
        for (const auto& w : warnings)
            if (w.find("unknown key") != std::string::npos)
                throw InputError(plan.source, "point " + p.name, w + " (an override names a key the file does not have)");
    }
}


namespace {

/// A drape plan's points (and so an experiment's drapes) are held to the drape's memory
/// estimate before the first starts: the largest of the points to run (up to 1,000 distinct
/// scenes and grids looked at), `jobs` of them at once sharing the machine's memory, each its
/// own address space.
void check_points_memory(const io::SweepPlan& plan, const std::vector<std::size_t>& todo, int jobs, int threads)
{
    if (plan.command != "drape" || todo.empty()) return;
    long long largest = 0;
    std::string at;
    std::set<std::string> seen;
    for (const std::size_t index : todo) {
        const io::SweepPoint p = plan.point(index);
        io::SceneOverrides ov;
        for (std::size_t k = 2; k + 1 < p.args.size(); ++k)
            if (p.args[k] == "--grid") ov.grid = std::stoi(p.args[k + 1]);
        std::string key = p.args[1] + "\n" + (ov.grid ? std::to_string(*ov.grid) : "");
        for (const auto& o : p.scene_overrides) key += "\n" + o.key + "=" + o.text;
        if (!seen.insert(key).second) continue;
        if (seen.size() > 1000) break;
        try {
            std::vector<std::string> warnings;
            io::SceneSpec scene = p.scene_overrides.empty()
                                      ? io::find_scene(p.args[1], &warnings)
                                      : io::parse_scene(io::apply_toml_overrides(io::scene_or_fabric_text(p.args[1], "scene"), p.args[1],
                                                                                 p.scene_overrides),
                                                        "scene " + p.args[1], ".", &warnings);
            io::apply_overrides(scene, ov, plan.source);
            const long long n = static_cast<long long>(scene.cloth.nu) * scene.cloth.nv;
            if (n > largest) {
                largest = n;
                at = p.name;
            }
        } catch (const InputError&) {
            // The point's own run reports it.
        }
    }
    if (largest == 0) return;
    MemoryEstimate e = estimate_drape_memory(largest, threads);
    const double at_once = static_cast<double>(std::min<std::size_t>(static_cast<std::size_t>(jobs), todo.size()));
    e.resident_bytes *= at_once;  // the address space is each point's own
    check_memory_estimate(e, largest, plan.source, "point " + at,
                          at_once > 1 ? "use a smaller grid or fewer --jobs (" + std::to_string(static_cast<int>(at_once)) + " points at once)" : "use a smaller grid");
}

}  // namespace

int sweep_signal_received() { return g_sweep_signal.load(); }

bool point_complete(const std::string& dir, const io::SweepPoint& point) { return point_state(dir, point).done; }

SweepRunResult run_sweep_points(const io::SweepPlan& plan, const std::string& out, const SweepRunOptions& o)
{
    SweepRunResult res;
    validate_sweep_overrides(plan);
    make_output_dir(out);
    require_own_folders(out);
    install_signal_handlers(on_sweep_signal);
    res.points = plan.size();
    std::vector<std::size_t> todo;
    for (std::size_t index = 0; index < plan.size(); ++index) {
        if (!in_shard(index, o.shard)) continue;
        const io::SweepPoint p = plan.point(index);
        ++res.mine;
        const PointState st = point_state(out, p);
        if (st.done) {
            ++res.done_before;
            continue;
        }
        if (!st.problem.empty()) std::cerr << "woven: warning: " << p.name << ": rerun: " << one_line(st.problem) << "\n";
        todo.push_back(index);
    }
    res.to_run = todo.size();
    const int jobs = o.jobs;
    const int cores = available_cores();
    const int threads = std::max(1, cores / (jobs * local_ranks()));
    check_points_memory(plan, todo, jobs, threads);
    std::cerr << "sweep " << plan.name << " (" << plan.command << "): " << plan.size() << " points";
    if (o.shard.count > 1)
        std::cerr << ", shard " << o.shard.index << "/" << o.shard.count << " (" << o.shard.source << "): " << res.mine << " here";
    std::cerr << "; " << res.done_before << " done already, " << todo.size() << " to run, " << jobs << (jobs == 1 ? " job" : " jobs")
              << " of " << threads_text(plan, todo, threads) << "; folder " << out << "\n"
              << std::flush;
    SweepRunner runner(plan, out, jobs, threads, o.on_start);
    res.failed = runner.run(todo);
    res.ran = runner.ran();
    if (g_sweep_signal.load() != 0) {
        res.signal = g_sweep_signal.load();
        std::cerr << "woven: sweep interrupted; " << runner.ran() << " points finished, the others run again next time\n";
        return res;
    }
    res.merged = merge_sweep(plan, out);
    std::cout << "ran " << res.ran << ", failed " << res.failed << "; merged: " << res.merged.done << " of " << plan.size() << " done, "
              << res.merged.failed << " failed, " << res.merged.missing << " missing (" << join_path(out, "sweep.csv") << ")\n";
    return res;
}

namespace {

int run_sweep(const SweepOptions& o)
{
    std::vector<std::string> warnings;
    const io::SweepPlan plan = io::load_sweep_plan(o.plan, &warnings);
    print_warnings(warnings);
    const std::string out = o.out ? parse_path(*o.out, "--out") : join_path("out", "sweep-" + plan.name);
    SweepRunOptions run;
    run.jobs = static_cast<int>(parse_integer(o.jobs, "--jobs", 1, 4096));
    run.shard = shard_from(o.shard, [](const char* name) { return std::getenv(name); });
    if (o.list || o.merge) {
        validate_sweep_overrides(plan);
        if (o.list) {
            // One point at a time (a million points are not held at once); every word shell-quoted
            // where it needs it, so that a pasted line runs the same command.
            std::string line;
            for (std::size_t index = 0; index < plan.size(); ++index) {
                const io::SweepPoint p = plan.point(index);
                line = std::to_string(p.index) + " " + p.name + (in_shard(p.index, run.shard) ? "" : " (other shard)") + ":";
                for (const auto& a : p.args) line += " " + shell_quote(a);
                for (const auto& v : p.scene_overrides) line += " " + shell_quote("scene." + v.key + "=" + v.text);
                for (const auto& v : p.fabric_overrides) line += " " + shell_quote("fabric." + v.key + "=" + v.text);
                line += "\n";
                std::cout << line;
            }
            return kExitOk;
        }
        make_output_dir(out);
        const MergeCounts c = merge_sweep(plan, out);
        std::cout << "merged " << plan.size() << " points into " << join_path(out, "sweep.csv") << " and " << join_path(out, "sweep.json")
                  << ": " << c.done << " done, " << c.failed << " failed, " << c.missing << " missing\n";
        return kExitOk;
    }
    const SweepRunResult r = run_sweep_points(plan, out, run);
    if (r.signal != 0) return 128 + r.signal;
    return r.failed > 0 ? kExitFailure : kExitOk;
}

}  // namespace

void add_sweep_command(CLI::App& app, int& exit_code)
{
    auto o = std::make_shared<SweepOptions>();
    CLI::App* sub = app.add_subcommand("sweep", "Run every point of a sweep plan (docs/SWEEP-FORMAT.md), resuming, on one machine or many");
    sub->footer("Each point runs the plan's command (drape, cusick or kes-test) as a child process and appears as <out>/<point>/ only "
                "once complete and verified (its manifest's SHA-256s and point.json). A point whose folder verifies is not run again; "
                "a failed or killed one is. The points are split by rank: --shard I/N, else Open MPI's OMPI_COMM_WORLD_RANK/SIZE, "
                "PMI_RANK/SIZE or Slurm's SLURM_ARRAY_TASK_ID/COUNT; every rank merges sweep.csv and sweep.json at its end, and "
                "--merge merges alone (idempotent). Exit 0 when every point of this shard is done, 1 when one failed, 130/143 when "
                "interrupted.");
    sub->add_option("PLAN", o->plan, "The plan, a .toml file")->required();
    sub->add_option("--out", o->out, "The sweep folder (default out/sweep-<plan name>)");
    sub->add_option("--jobs", o->jobs, "Points run at once on this machine (the cores are divided between them)")->capture_default_str()->type_name("INT");
    sub->add_option("--shard", o->shard, "Run shard I of N (0 <= I < N): the points whose index modulo N is I");
    sub->add_flag("--merge", o->merge, "Only merge the finished points into sweep.csv and sweep.json");
    sub->add_flag("--list", o->list, "List the points and their command lines, run nothing");
    sub->callback([o, &exit_code] { exit_code = run_sweep(*o); });
}

}  // namespace woven::cli
