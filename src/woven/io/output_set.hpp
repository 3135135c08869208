#pragma once
// A set of output files that appears in its directory whole or is recognisably incomplete.
//
// Every file is first written under a unique temporary name in the output directory
// (".woven-tmp.<pid>.<n>.<name>"). publish() then, holding an exclusive flock on the directory
// (so two runs sharing a directory take turns): removes the old manifest,
// renames the new files into place, removes every other file the earlier manifest lists, and
// writes the manifest (report.json) last, naming every file of the set with its size and
// SHA-256 (SIGINT, SIGTERM and SIGHUP wait while it does: raised again once it is done, so only
// SIGKILL can stop a publish half way). A directory holds a complete set exactly when its manifest exists and every file it
// names has that checksum. Temporaries of processes that no longer run are removed when a set
// is opened; an unpublished set removes its own when destroyed.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

namespace woven::io {

/// Prefix of the temporary files of an output set.
inline constexpr std::string_view kTempPrefix = ".woven-tmp.";

/// Removes "<dir>/.woven-tmp.<pid>.*" left by processes that are no longer running; returns
/// how many entries were removed.
int remove_stale_temporaries(const std::string& dir);

/// Opens `dir` and holds it until an OutputSet is made for `dir` (the same string): that set
/// writes into the folder held even if the path has been replaced meanwhile (a symlink swapped
/// in while a run works does not redirect its outputs). Held already: kept (unless deleted).
/// RuntimeError when it cannot be opened.
void hold_output_dir(const std::string& dir);

class OutputSet {
public:
    /// `dir` must exist. `members`: every file name the set can hold (besides the manifest),
    /// checked at publish to be no folder. Every file the earlier set's manifest lists (plain
    /// names in `dir`, not hidden) that this run does not write is removed at publish, member or
    /// not. Removes stale temporaries.
    OutputSet(std::string dir, std::vector<std::string> members);
    OutputSet(const OutputSet&) = delete;
    OutputSet& operator=(const OutputSet&) = delete;
    ~OutputSet();

    /// Writes `contents` as the set's file `name` (under its temporary name).
    void add(const std::string& name, std::string_view contents);
    /// A temporary path for a writer that writes the file itself (render::write_png); call
    /// added(name) once it has.
    std::string temp_path(const std::string& name);
    /// Records a file written at temp_path(name).
    void added(const std::string& name);

    /// {"<name>": {"bytes": n, "sha256": "<hex>"}} for every file added so far.
    nlohmann::json files_json() const;
    /// Names of the files added, in order.
    std::vector<std::string> names() const;

    /// Publishes the set as described above, the manifest `manifest_name` last.
    /// RuntimeError when a file cannot be moved into place (the set is then left without a
    /// manifest, i.e. recognisably incomplete).
    void publish(const std::string& manifest_name, std::string_view manifest_contents);

private:
    struct File {
        std::string name, temp;
        std::uint64_t bytes = 0;
        std::string sha256;
    };
    std::string dir_;
    int dirfd_ = -1;  ///< the folder, held open: every file is written, renamed and removed through it
    std::vector<std::string> members_;
    std::vector<File> files_;
    std::vector<std::string> temps_;  ///< temporaries that exist and are not yet renamed
    bool published_ = false;
};

}  // namespace woven::io
