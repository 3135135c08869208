#pragma once
// Reading back what woven wrote into an output folder (a manifest, point.json, failed/*.json,
// sweep.json, a listed member of a set): the folder may have been changed by anyone since, so
// these are read as carefully as input files. Regular files only (a FIFO does not block, a link
// to /dev/zero is not read), bounded in size, and JSON nested at most kMaxOutputJsonDepth deep
// (counted before the parser runs: 60,000 levels crashed it).
#include <cstddef>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace woven::io {

/// A manifest (report.json, cusick.json, kes-report.json), point.json or a failure record.
inline constexpr std::size_t kMaxManifestBytes = 16u << 20;
/// A sweep's merged table (about 600 bytes a point: a million points fit).
inline constexpr std::size_t kMaxSweepTableBytes = 1024u << 20;
/// A file a manifest lists (a mesh, a picture, a table).
inline constexpr std::size_t kMaxSetMemberBytes = 1024u << 20;
/// The deepest nesting of any JSON woven writes is 5; this leaves room and no recursion risk.
inline constexpr int kMaxOutputJsonDepth = 64;

/// The deepest nesting of arrays and objects in `text` (brackets outside strings), counting
/// no further than `stop` + 1.
int json_depth(std::string_view text, int stop);

/// `text` parsed as JSON. InputError(source, "json", ...): nested deeper than `max_depth`
/// ("expected <expected> nested at most 64 deep"), not JSON ("expected <expected> (not JSON:
/// syntax error at byte N)"), a number beyond double's range.
nlohmann::json parse_output_json(std::string_view text, const std::string& source, const std::string& expected,
                                 int max_depth = kMaxOutputJsonDepth);

/// The regular file `path` (at most `limit` bytes) parsed as JSON: InputError as
/// io::read_input_file for the file ("is not a regular file (a device, FIFO or socket)...",
/// "expected <expected> of at most N MiB, got M bytes") and as parse_output_json for the JSON.
nlohmann::json read_output_json(const std::string& path, std::size_t limit, const std::string& expected);

/// The whole of the regular file `path` a set lists, at most `limit` bytes (io::read_input_file).
std::string read_output_member(const std::string& path, std::size_t limit = kMaxSetMemberBytes);

}  // namespace woven::io
