// The sweep's process pool (sweep.hpp): runs the points of a plan to run, `jobs` at once, each a
// child process of this binary running the plan's command into a private work folder; a point
// that finishes and verifies is renamed into place as <sweep>/<point name>/, so a point's folder
// is there complete (its manifest, every file's SHA-256, point.json) or not at all. Resume is
// the default: a point whose folder verifies with the plan's command line is not run again.
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

#include <nlohmann/json.hpp>

#include "woven/app/check.hpp"
#include "woven/app/files.hpp"
#include "woven/app/progress.hpp"
#include "woven/common/format.hpp"
#include "woven/sim/resources.hpp"
#include "woven/app/run_checks.hpp"
#include "woven/batch/sweep.hpp"
#include "woven/batch/sweep_parts.hpp"
#include "woven/common/error.hpp"
#include "woven/io/fabric_file.hpp"
#include "woven/io/output_file.hpp"
#include "woven/io/scene_file.hpp"
#include "woven/batch/sweep_plan.hpp"

namespace woven::batch {

using namespace woven::app;

namespace fs = std::filesystem;

namespace {

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

/// A point that is running: its child and work folder.
struct Running {
    pid_t pid = -1;
    batch::SweepPoint point;
    fs::path work;
    std::chrono::steady_clock::time_point start;
    std::chrono::steady_clock::time_point said;  ///< its progress last relayed (relay_progress)
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
std::string threads_text(const batch::SweepPlan& plan, const std::vector<std::size_t>& todo, int share)
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
    SweepRunner(const batch::SweepPlan& plan, fs::path sweep, int jobs, int threads_per_point, const SweepRunOptions& o)
        : plan_(plan), sweep_(std::move(sweep)), work_root_(sweep_ / ".work"), jobs_(jobs), threads_(threads_per_point),
          host_(host_name()), executable_(o.executable), on_start_(o.on_start), on_line_(o.on_line)
    {
    }

    /// Runs the points of the plan numbered `todo`; returns the number that failed.
    int run(const std::vector<std::size_t>& todo)
    {
        fs::create_directories(work_root_);
        fs::create_directories(sweep_ / "failed");
        // Held open from here (never by its path again): a link planted in its place while the
        // sweep runs is not followed (issue 53: 30 failure records written outside the sweep).
        failed_fd_ = ::open((sweep_ / "failed").c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
        if (failed_fd_ < 0)
            throw RuntimeError((sweep_ / "failed").string() + ": cannot open the sweep's failure folder: " + std::strerror(errno)
                               + " (expected the sweep's own folder, not a link)");
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
                relay_progress(running);
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
    std::vector<std::string> command_line(const batch::SweepPoint& p, const fs::path& work)
    {
        std::vector<std::string> args = p.args;
        if (!p.scene_overrides.empty()) {
            const std::string scene = args[1];
            const std::string text = batch::scene_or_fabric_text(scene, "scene");
            const fs::path file = work / "scene.toml";
            std::ofstream(file) << batch::apply_toml_overrides(text, scene, p.scene_overrides);
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
            const std::string text = batch::scene_or_fabric_text(fabric, "fabric");
            const fs::path file = work / "fabric.toml";
            std::ofstream(file) << batch::apply_toml_overrides(text, fabric, p.fabric_overrides);
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

    Running start(batch::SweepPoint point)
    {
        Running r;
        r.point = std::move(point);
        const batch::SweepPoint& p = r.point;
        r.work = work_root_ / (p.name + "." + host_ + "." + std::to_string(::getpid()));
        std::error_code ec;
        fs::remove_all(r.work, ec);
        fs::create_directories(r.work);
        r.args = command_line(p, r.work);
        const std::string log = (r.work / "log.txt").string();
        std::vector<char*> argv;
        std::string argv0 = "woven";
        argv.push_back(argv0.data());
        for (auto& a : r.args) argv.push_back(a.data());
        argv.push_back(nullptr);
        const pid_t parent = ::getpid();
        r.start = r.said = std::chrono::steady_clock::now();
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
            ::execv(executable_.c_str(), argv.data());
            ::_exit(127);
        }
        r.pid = pid;
        if (on_start_) on_start_(p);
        return r;
    }

    void finish(const Running& r, int status, std::size_t finished, std::size_t total)
    {
        const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - r.start).count();
        const batch::SweepPoint& p = r.point;
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
            const std::string record = write_failure(p.name + ".json", f.dump(2) + "\n");
            remove_work(r.work);
            std::ostringstream line;
            line << head.str() << "FAILED (" << problem << ", " << std::fixed << std::setprecision(1) << wall << " s); "
                 << (record.empty() ? "see " + (sweep_ / "failed" / (p.name + ".json")).string() : record);
            say(line.str());
            return;
        }
        nlohmann::json pj = point_json(p);
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
                say(head.str() + "done elsewhere meanwhile; kept that folder");
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
        ::unlinkat(failed_fd_, (p.name + ".json").c_str(), 0);  // through the folder held: a link in its place is not followed
        ++ran_;
        head << "ran in " << std::fixed << std::setprecision(1) << wall << " s";
        say(head.str());
    }

    /// Each running point's progress, every kPointProgressS seconds: the last line of its log
    /// (the point's own progress display, which speaks at least every 2 s), prefixed by the
    /// point; a point that has said nothing yet, how long it has run (issue 53: a sweep was
    /// silent while its points ran, 23 s for one 41 x 41 drape).
    void relay_progress(std::vector<Running>& running)
    {
        constexpr double kPointProgressS = 2.0;
        const auto now = std::chrono::steady_clock::now();
        for (Running& r : running) {
            if (std::chrono::duration<double>(now - r.said).count() < kPointProgressS) continue;
            r.said = now;
            std::string last = tail_lines(r.work / "log.txt", 1);
            while (!last.empty() && (last.back() == '\n' || last.back() == '\r')) last.pop_back();
            if (const auto cr = last.rfind('\r'); cr != std::string::npos) last = last.substr(cr + 1);  // a bar redrawn in place
            if (last.rfind("woven: ", 0) == 0) last = last.substr(7);
            const double t = std::chrono::duration<double>(now - r.start).count();
            say("  " + r.point.name + ": " + (last.empty() ? "running" : last.substr(0, 160)) + strf(" (point %.0f s)", t));
        }
    }

    /// A line of word on the run (stderr), to on_line.
    void say(const std::string& line)
    {
        if (on_line_) on_line_(line, false);
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

    const batch::SweepPlan& plan_;
    fs::path sweep_, work_root_;
    int jobs_, threads_;
    std::string host_;
    std::string executable_;
    std::function<void(const batch::SweepPoint&)> on_start_;
    std::function<void(const std::string&, bool)> on_line_;
    int failed_ = 0, ran_ = 0;
    int failed_fd_ = -1;  ///< the failure folder, held open by run()

    /// Writes a failure record into the folder held (a temporary, then renamed, both through the
    /// descriptor, no link followed); "" when written, else why not (the folder was removed).
    std::string write_failure(const std::string& name, const std::string& text)
    {
        static std::atomic<int> counter{0};
        const std::string tmp = ".woven-tmp." + std::to_string(::getpid()) + "." + std::to_string(counter++) + "." + name;
        const int fd = ::openat(failed_fd_, tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
        bool ok = fd >= 0;
        for (std::size_t done = 0; ok && done < text.size();) {
            const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
            if (n < 0 && errno == EINTR) continue;
            ok = n > 0;
            if (ok) done += static_cast<std::size_t>(n);
        }
        const int err = errno;
        if (fd >= 0) ::close(fd);
        if (ok && ::renameat(failed_fd_, tmp.c_str(), failed_fd_, name.c_str()) == 0) return "";
        ::unlinkat(failed_fd_, tmp.c_str(), 0);
        return "its failure record was not written (" + std::string(std::strerror(ok ? errno : err))
            + ": the sweep's failed/ folder was removed or replaced)";
    }

public:
    SweepRunner(const SweepRunner&) = delete;
    SweepRunner& operator=(const SweepRunner&) = delete;
    ~SweepRunner()
    {
        if (failed_fd_ >= 0) ::close(failed_fd_);
    }
};

}  // namespace

int sweep_signal_received() { return g_sweep_signal.load(); }

SweepRunResult run_sweep_points(const batch::SweepPlan& plan, const std::string& out, const SweepRunOptions& o)
{
    SweepRunResult res;
    if (o.executable.empty()) throw RuntimeError("sweep: no woven executable given to run the points");
    validate_sweep_overrides(plan);
    make_output_dir(out);
    require_own_folders(out);
    install_signal_handlers(on_sweep_signal);
    res.points = plan.size();
    std::vector<std::size_t> todo;
    for (std::size_t index = 0; index < plan.size(); ++index) {
        if (!in_shard(index, o.shard)) continue;
        const batch::SweepPoint p = plan.point(index);
        ++res.mine;
        const PointState st = point_state(out, p);
        if (st.done) {
            ++res.done_before;
            continue;
        }
        if (!st.problem.empty() && o.on_line) o.on_line("woven: warning: " + p.name + ": rerun: " + one_line(st.problem), false);
        todo.push_back(index);
    }
    res.to_run = todo.size();
    const int jobs = o.jobs;
    const int cores = sim::available_cores();
    const int threads = std::max(1, cores / (jobs * local_ranks()));
    check_points_memory(plan, todo, jobs, threads);
    std::ostringstream head;
    head << "sweep " << plan.name << " (" << plan.command << "): " << plan.size() << " points";
    if (o.shard.count > 1) head << ", shard " << o.shard.index << "/" << o.shard.count << " (" << o.shard.source << "): " << res.mine << " here";
    head << "; " << res.done_before << " done already, " << todo.size() << " to run, " << jobs << (jobs == 1 ? " job" : " jobs") << " of "
         << threads_text(plan, todo, threads) << "; folder " << out;
    if (o.on_line) o.on_line(head.str(), false);
    SweepRunner runner(plan, out, jobs, threads, o);
    res.failed = runner.run(todo);
    res.ran = runner.ran();
    if (g_sweep_signal.load() != 0) {
        res.signal = g_sweep_signal.load();
        if (o.on_line) o.on_line("woven: sweep interrupted; " + std::to_string(runner.ran()) + " points finished, the others run again next time", false);
        return res;
    }
    res.merged = merge_sweep(plan, out);
    if (o.on_line)
        o.on_line("ran " + std::to_string(res.ran) + ", failed " + std::to_string(res.failed) + "; merged: " + std::to_string(res.merged.done) +
                      " of " + std::to_string(plan.size()) + " done, " + std::to_string(res.merged.failed) + " failed, " +
                      std::to_string(res.merged.missing) + " missing (" + join_path(out, "sweep.csv") + ")",
                  true);
    return res;
}

}  // namespace woven::batch
