// The sweep's folder (sweep_parts.hpp, sweep.hpp): its lock, its files written atomically and
// the state of a point's folder.
#include "woven/batch/sweep_parts.hpp"

#include <atomic>
#include <cerrno>
#include <cstring>
#include <fstream>

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include "woven/app/check.hpp"
#include "woven/app/files.hpp"
#include "woven/batch/sweep.hpp"
#include "woven/common/error.hpp"
#include "woven/io/output_file.hpp"

namespace woven::batch {

using namespace woven::app;

namespace fs = std::filesystem;

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

nlohmann::json point_signature(const batch::SweepPoint& p)
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

std::optional<nlohmann::json> read_sweep_json(const fs::path& p, std::string* why)
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
        if (fs::exists(dir / m)) return read_sweep_json(dir / m);
    return std::nullopt;
}

nlohmann::json value_json(const batch::SweepValue& v)
{
    if (!v.number) return v.text;
    if (v.text.find_first_of(".eEn") == std::string::npos) return std::stoll(v.text);
    return std::stod(v.text);
}

nlohmann::json point_json(const batch::SweepPoint& p)
{
    nlohmann::json values = nlohmann::json::object();
    for (const auto& v : p.values) values[v.key] = value_json(v);
    return {{"point", p.name}, {"index", p.index}, {"values", values}};
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

PointState point_state(const fs::path& sweep, const batch::SweepPoint& p)
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
    const auto pj = read_sweep_json(dir / "point.json", &why);
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

bool point_complete(const std::string& dir, const batch::SweepPoint& point) { return point_state(dir, point).done; }

}  // namespace woven::batch
