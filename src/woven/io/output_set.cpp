#include "woven/io/output_set.hpp"

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <map>
#include <mutex>
#include <optional>
#include <set>

#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/file.h>
#include <unistd.h>

#include "woven/common/error.hpp"
#include "woven/io/output.hpp"
#include "woven/io/output_file.hpp"
#include "woven/io/sha256.hpp"

namespace woven::io {

namespace fs = std::filesystem;

namespace {

/// Numbers the temporaries of this process (all its sets, all threads).
std::atomic<long> g_temp_counter{0};

std::string path_in(const std::string& dir, const std::string& name) { return (fs::path(dir) / name).string(); }

/// The folders this process holds open (hold_output_dir), by the path given.
std::mutex g_held_mutex;
std::map<std::string, int>& held_dirs()
{
    static std::map<std::string, int> held;
    return held;
}

/// The folder `dir`: the descriptor held for it (taken: the next run in this process holds the
/// path afresh), else the folder opened now.
int open_dir(const std::string& dir)
{
    {
        const std::lock_guard<std::mutex> lock(g_held_mutex);
        if (const auto it = held_dirs().find(dir); it != held_dirs().end()) {
            const int fd = it->second;
            held_dirs().erase(it);
            return fd;
        }
    }
    return ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
}

/// "/proc/self/fd/<fd>": the held folder as a path that a swapped symlink does not redirect
/// (for writers that take a path); `dir` itself where /proc is not mounted.
std::string fd_path(int fd, const std::string& dir)
{
    static const bool proc = ::access("/proc/self/fd", X_OK) == 0;
    return proc ? "/proc/self/fd/" + std::to_string(fd) : dir;
}

/// The whole of the regular file `name` in the folder `dirfd` (not followed if a symlink), at
/// most `limit` bytes; nullopt when it is not there or not such a file.
std::optional<std::string> read_at(int dirfd, const std::string& name, std::size_t limit)
{
    const int fd = ::openat(dirfd, name.c_str(), O_RDONLY | O_NONBLOCK | O_NOFOLLOW | O_CLOEXEC | O_NOCTTY);
    if (fd < 0) return std::nullopt;
    struct stat st {};
    std::optional<std::string> out;
    if (::fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && static_cast<std::size_t>(st.st_size) <= limit) {
        std::string text;
        char buf[65536];
        for (;;) {
            const ssize_t r = ::read(fd, buf, sizeof buf);
            if (r < 0 && errno == EINTR) continue;
            if (r <= 0 || text.size() + static_cast<std::size_t>(r) > limit) {
                if (r == 0) out = std::move(text);
                break;
            }
            text.append(buf, static_cast<std::size_t>(r));
        }
    }
    ::close(fd);
    return out;
}

/// Writes `contents` to the new file `name` in the folder `dirfd`, RuntimeError on any failure.
void write_all(int dirfd, const std::string& name, std::string_view contents, const std::string& shown)
{
    const int fd = ::openat(dirfd, name.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
    if (fd < 0) throw RuntimeError(shown + ": cannot write: " + std::strerror(errno));
    std::size_t n = 0;
    int e = 0;
    while (n < contents.size()) {
        const ssize_t w = ::write(fd, contents.data() + n, contents.size() - n);
        if (w < 0 && errno == EINTR) continue;
        if (w <= 0) {
            e = w < 0 ? errno : EIO;
            break;
        }
        n += static_cast<std::size_t>(w);
    }
    if (::close(fd) != 0 && e == 0) e = errno;
    if (e != 0) {
        ::unlinkat(dirfd, name.c_str(), 0);
        throw RuntimeError(shown + ": write failed: " + std::strerror(e));
    }
}

/// An exclusive flock on the directory itself for the scope (Linux locks directories too, so
/// no lock file is left behind), on a description of its own (a dup would share the lock).
class DirLock {
public:
    DirLock(int dirfd, const std::string& dir)
    {
        fd_ = ::openat(dirfd, ".", O_RDONLY | O_DIRECTORY | O_CLOEXEC);
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

/// The files the manifest `name` in `dirfd` lists (its "files" object's keys, or a list of names).
std::set<std::string> listed_files(int dirfd, const std::string& name, const std::string& shown)
{
    std::set<std::string> out;
    const auto text = read_at(dirfd, name, kMaxManifestBytes);
    if (!text) return out;
    try {
        const nlohmann::json j = parse_output_json(*text, shown, "a manifest");
        if (!j.is_object() || !j.contains("files")) return out;
        const auto& f = j["files"];
        if (f.is_object())
            for (auto it = f.begin(); it != f.end(); ++it) out.insert(it.key());
        if (f.is_array())
            for (const auto& n : f)
                if (n.is_string()) out.insert(n.get<std::string>());
    } catch (const InputError&) {
    }
    return out;
}

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

namespace {

int remove_stale_temporaries_at(int dirfd)
{
    int removed = 0;
    const int fd = ::openat(dirfd, ".", O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) return 0;
    DIR* d = ::fdopendir(fd);
    if (!d) {
        ::close(fd);
        return 0;
    }
    std::vector<std::string> names;
    while (const dirent* e = ::readdir(d)) names.emplace_back(e->d_name);
    ::closedir(d);
    for (const auto& name : names) {
        if (name.rfind(kTempPrefix, 0) != 0) continue;
        // ".woven-tmp.<pid>.<n>.<name>": stale when no process <pid> runs.
        const std::string rest = name.substr(kTempPrefix.size());
        char* end_ptr = nullptr;
        const long pid = std::strtol(rest.c_str(), &end_ptr, 10);
        if (end_ptr == rest.c_str() || *end_ptr != '.' || pid <= 0) continue;
        if (pid == ::getpid() || ::kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH) continue;
        if (::unlinkat(dirfd, name.c_str(), 0) == 0) ++removed;
    }
    return removed;
}

}  // namespace

int remove_stale_temporaries(const std::string& dir)
{
    const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) return 0;
    const int removed = remove_stale_temporaries_at(fd);
    ::close(fd);
    return removed;
}

void hold_output_dir(const std::string& dir)
{
    const std::lock_guard<std::mutex> lock(g_held_mutex);
    if (const auto it = held_dirs().find(dir); it != held_dirs().end()) {
        // Held already (a command checks --out again before it publishes): kept, unless that
        // folder has been deleted since (a run that failed before its set, then the folder removed).
        struct stat st {};
        if (::fstat(it->second, &st) == 0 && st.st_nlink > 0) return;
        ::close(it->second);
        held_dirs().erase(it);
    }
    const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) throw RuntimeError(dir + ": cannot open the output directory: " + std::strerror(errno));
    held_dirs()[dir] = fd;
}

OutputSet::OutputSet(std::string dir, std::vector<std::string> members) : dir_(std::move(dir)), members_(std::move(members))
{
    dirfd_ = open_dir(dir_);
    if (dirfd_ < 0) throw RuntimeError(dir_ + ": cannot open the output directory: " + std::strerror(errno));
    remove_stale_temporaries_at(dirfd_);
}

OutputSet::~OutputSet()
{
    for (const auto& t : temps_) {
        ::unlinkat(dirfd_, t.c_str(), 0);
        ::unlinkat(dirfd_, (t + ".tmp").c_str(), 0);  // render::write_png's own temporary
    }
    ::close(dirfd_);
}

std::string OutputSet::temp_path(const std::string& name)
{
    const std::string t = std::string(kTempPrefix) + std::to_string(::getpid()) + "." + std::to_string(g_temp_counter++) + "." + name;
    temps_.push_back(t);
    return path_in(fd_path(dirfd_, dir_), t);
}

void OutputSet::added(const std::string& name)
{
    File f;
    f.name = name;
    f.temp = temps_.back();
    const auto data = read_at(dirfd_, f.temp, std::numeric_limits<std::size_t>::max());
    if (!data) throw RuntimeError(path_in(dir_, name) + ": cannot read back the file written");
    f.bytes = data->size();
    f.sha256 = sha256_hex(*data);
    files_.push_back(std::move(f));
}

void OutputSet::add(const std::string& name, std::string_view contents)
{
    std::string t = std::string(kTempPrefix) + std::to_string(::getpid()) + "." + std::to_string(g_temp_counter++) + "." + name;
    temps_.push_back(t);
    write_all(dirfd_, t, contents, path_in(dir_, name));
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
    const std::string manifest_temp = std::string(kTempPrefix) + std::to_string(::getpid()) + "." +
                                      std::to_string(g_temp_counter++) + "." + manifest_name;
    temps_.push_back(manifest_temp);
    write_all(dirfd_, manifest_temp, manifest_contents, path_in(dir_, manifest_name));
    const DeferSignals defer;  // declared before the lock: a deferred signal is raised after it is released
    const DirLock lock(dirfd_, dir_);
    // Nothing that is in the way may be a directory (or anything but a file): check first, so
    // that a failure leaves the previous set as it was.
    std::vector<std::string> targets = members_;
    targets.push_back(manifest_name);
    for (const auto& f : files_) targets.push_back(f.name);
    for (const auto& name : targets) {
        struct stat st {};
        if (::fstatat(dirfd_, name.c_str(), &st, AT_SYMLINK_NOFOLLOW) == 0 && !S_ISREG(st.st_mode))
            throw RuntimeError(path_in(dir_, name) + ": exists and is not a regular file; the outputs were not written");
    }
    // Only the files the previous set's manifest lists are its (a file of the user's own with a
    // member's name stays).
    const std::set<std::string> earlier = listed_files(dirfd_, manifest_name, path_in(dir_, manifest_name));
    const std::string manifest = path_in(dir_, manifest_name);
    if (::unlinkat(dirfd_, manifest_name.c_str(), 0) != 0 && errno != ENOENT)
        throw RuntimeError(manifest + ": cannot remove the previous manifest: " + std::strerror(errno));
    for (const auto& f : files_) {
        const std::string to = path_in(dir_, f.name);
        if (::renameat(dirfd_, f.temp.c_str(), dirfd_, f.name.c_str()) != 0)
            throw RuntimeError(to + ": cannot move into place: " + std::strerror(errno) + " (the set is incomplete: no " +
                               manifest_name + ")");
        std::erase(temps_, f.temp);
    }
    // Every file the earlier manifest lists that this run does not write: the earlier set's
    // (cusick --seeds 3 then --seeds 1 left shadow-seed*.png beside the new set's shadow.png).
    // Only plain names in this folder, never the manifest, a temporary or a folder: the list
    // is read from a file anyone may have changed.
    std::set<std::string> written{manifest_name};
    for (const auto& f : files_) written.insert(f.name);
    for (const auto& m : earlier) {
        if (written.count(m) || m.empty() || m.front() == '.' || m.find('/') != std::string::npos || m.find('\0') != std::string::npos)
            continue;
        struct stat st {};
        if (::fstatat(dirfd_, m.c_str(), &st, AT_SYMLINK_NOFOLLOW) == 0 && (S_ISREG(st.st_mode) || S_ISLNK(st.st_mode)))
            ::unlinkat(dirfd_, m.c_str(), 0);
    }
    if (::renameat(dirfd_, manifest_temp.c_str(), dirfd_, manifest_name.c_str()) != 0)
        throw RuntimeError(manifest + ": cannot move into place: " + std::strerror(errno));
    std::erase(temps_, manifest_temp);
    published_ = true;
}

}  // namespace woven::io
