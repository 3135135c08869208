#include "woven/io/output_set.hpp"

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <unistd.h>

#include "woven/common/error.hpp"
#include "woven/io/output.hpp"
#include "woven/io/sha256.hpp"

namespace woven::io {

namespace fs = std::filesystem;

namespace {

/// Numbers the temporaries of this process (all its sets, all threads).
std::atomic<long> g_temp_counter{0};

std::string path_in(const std::string& dir, const std::string& name) { return (fs::path(dir) / name).string(); }

std::string read_file(const std::string& path)
{
    std::ifstream in(path, std::ios::binary);
    if (!in) throw RuntimeError(path + ": cannot read back the file written: " + std::strerror(errno));
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

/// Writes `contents` to `path` (a fresh temporary name), RuntimeError on any failure.
void write_all(const std::string& path, std::string_view contents, const std::string& shown)
{
    std::FILE* f = std::fopen(path.c_str(), "wbx");
    if (!f) throw RuntimeError(shown + ": cannot write: " + std::strerror(errno));
    const std::size_t n = std::fwrite(contents.data(), 1, contents.size(), f);
    const int e = errno;
    const bool ok = n == contents.size() && std::fflush(f) == 0;
    const int e2 = errno;
    if (std::fclose(f) != 0 || !ok) {
        std::remove(path.c_str());
        throw RuntimeError(shown + ": write failed: " + std::strerror(n != contents.size() ? e : e2));
    }
}

/// An exclusive flock on the directory itself for the scope (Linux locks directories too, so
/// no lock file is left behind).
class DirLock {
public:
    explicit DirLock(const std::string& dir)
    {
        fd_ = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
        if (fd_ < 0) throw RuntimeError(dir + ": cannot open the output directory: " + std::strerror(errno));
        while (::flock(fd_, LOCK_EX) != 0)
            if (errno != EINTR) throw RuntimeError(dir + ": cannot lock the output directory: " + std::strerror(errno));
    }
    DirLock(const DirLock&) = delete;
    DirLock& operator=(const DirLock&) = delete;
    ~DirLock() { ::close(fd_); }  // closing releases the lock

private:
    int fd_ = -1;
};

/// SIGINT, SIGTERM and SIGHUP wait while a set is published: for the scope a handler only
/// records them; at its end the previous handlers are restored and a recorded signal is raised
/// again (the default action then ends the process, woven's own handler sets its flag). So a
/// signal never stops a publish half way (SIGKILL still can: the set then has no manifest).
std::atomic<int> g_deferred_signal{0};

extern "C" void record_signal(int sig)
{
    int none = 0;
    g_deferred_signal.compare_exchange_strong(none, sig);
}

class DeferSignals {
public:
    DeferSignals()
    {
        struct sigaction sa {};
        sa.sa_handler = record_signal;
        sigemptyset(&sa.sa_mask);
        sa.sa_flags = SA_RESTART;
        for (int k = 0; k < 3; ++k) sigaction(kSignals[k], &sa, &old_[k]);
    }
    DeferSignals(const DeferSignals&) = delete;
    DeferSignals& operator=(const DeferSignals&) = delete;
    ~DeferSignals()
    {
        for (int k = 0; k < 3; ++k) sigaction(kSignals[k], &old_[k], nullptr);
        if (const int sig = g_deferred_signal.exchange(0)) ::raise(sig);
    }

private:
    static constexpr int kSignals[3] = {SIGINT, SIGTERM, SIGHUP};
    struct sigaction old_[3] {};
};

}  // namespace

int remove_stale_temporaries(const std::string& dir)
{
    int removed = 0;
    std::error_code ec;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        if (name.rfind(kTempPrefix, 0) != 0) continue;
        // ".woven-tmp.<pid>.<n>.<name>": stale when no process <pid> runs.
        const std::string rest = name.substr(kTempPrefix.size());
        char* end_ptr = nullptr;
        const long pid = std::strtol(rest.c_str(), &end_ptr, 10);
        if (end_ptr == rest.c_str() || *end_ptr != '.' || pid <= 0) continue;
        if (pid == ::getpid() || ::kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH) continue;
        std::error_code rm;
        if (fs::remove(it->path(), rm)) ++removed;
    }
    return removed;
}

OutputSet::OutputSet(std::string dir, std::vector<std::string> members) : dir_(std::move(dir)), members_(std::move(members))
{
    remove_stale_temporaries(dir_);
}

OutputSet::~OutputSet()
{
    for (const auto& t : temps_) {
        std::remove(t.c_str());
        std::remove((t + ".tmp").c_str());  // render::write_png's own temporary
    }
}

std::string OutputSet::temp_path(const std::string& name)
{
    const std::string t = path_in(dir_, std::string(kTempPrefix) + std::to_string(::getpid()) + "." +
                                            std::to_string(g_temp_counter++) + "." + name);
    temps_.push_back(t);
    return t;
}

void OutputSet::added(const std::string& name)
{
    File f;
    f.name = name;
    f.temp = temps_.back();
    const std::string data = read_file(f.temp);
    f.bytes = data.size();
    f.sha256 = sha256_hex(data);
    files_.push_back(std::move(f));
}

void OutputSet::add(const std::string& name, std::string_view contents)
{
    const std::string t = temp_path(name);
    write_all(t, contents, path_in(dir_, name));
    File f;
    f.name = name;
    f.temp = t;
    f.bytes = contents.size();
    f.sha256 = sha256_hex(contents);
    files_.push_back(std::move(f));
}

nlohmann::json OutputSet::files_json() const
{
    nlohmann::json j = nlohmann::json::object();
    for (const auto& f : files_) j[f.name] = {{"bytes", f.bytes}, {"sha256", f.sha256}};
    return j;
}

std::vector<std::string> OutputSet::names() const
{
    std::vector<std::string> n;
    for (const auto& f : files_) n.push_back(f.name);
    return n;
}

void OutputSet::publish(const std::string& manifest_name, std::string_view manifest_contents)
{
    const std::string manifest_temp = temp_path(manifest_name);
    write_all(manifest_temp, manifest_contents, path_in(dir_, manifest_name));
    const DeferSignals defer;  // declared before the lock: a deferred signal is raised after it is released
    const DirLock lock(dir_);
    // Nothing that is in the way may be a directory (or anything but a file): check first, so
    // that a failure leaves the previous set as it was.
    std::vector<std::string> targets = members_;
    targets.push_back(manifest_name);
    for (const auto& f : files_) targets.push_back(f.name);
    for (const auto& name : targets) {
        std::error_code ec;
        const auto st = fs::symlink_status(path_in(dir_, name), ec);
        if (!ec && fs::exists(st) && !fs::is_regular_file(st))
            throw RuntimeError(path_in(dir_, name) + ": exists and is not a regular file; the outputs were not written");
    }
    const std::string manifest = path_in(dir_, manifest_name);
    if (std::remove(manifest.c_str()) != 0 && errno != ENOENT)
        throw RuntimeError(manifest + ": cannot remove the previous manifest: " + std::strerror(errno));
    for (const auto& f : files_) {
        const std::string to = path_in(dir_, f.name);
        if (std::rename(f.temp.c_str(), to.c_str()) != 0)
            throw RuntimeError(to + ": cannot move into place: " + std::strerror(errno) + " (the set is incomplete: no " +
                               manifest_name + ")");
        std::erase(temps_, f.temp);
    }
    for (const auto& m : members_) {
        bool written = false;
        for (const auto& f : files_) written = written || f.name == m;
        if (!written) std::remove(path_in(dir_, m).c_str());  // an earlier run's file, not of this set
    }
    if (std::rename(manifest_temp.c_str(), manifest.c_str()) != 0)
        throw RuntimeError(manifest + ": cannot move into place: " + std::strerror(errno));
    std::erase(temps_, manifest_temp);
    published_ = true;
}

}  // namespace woven::io
