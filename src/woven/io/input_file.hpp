#pragma once
// Reading an input file whole, bounded: every file woven reads (fabric, scene, mesh OBJ, the
// corner map `experiment map --reuse` analyses again) goes through read_input_file, so that a
// device (/dev/zero), a FIFO or a directory is refused at once instead of read for ever (or
// blocking), and no more than the limit + 1 byte is ever read.
#include <cstddef>
#include <string>

namespace woven::io {

/// What a file is, for its errors: "no such <noun>", "is a directory; expected <expected>".
struct InputKind {
    std::string noun;      ///< "fabric file"
    std::string expected;  ///< "a fabric .toml file"
};

/// The whole of the regular file `path`, at most `limit` bytes. Throws InputError(path, "file", ...):
///   "no such <noun>" (it does not exist), "is a directory; expected <expected>",
///   "is not a regular file (a device, FIFO or socket); expected <expected>",
///   "expected <expected> of at most <n> MiB, got <size> bytes" (reading stops at
///   limit + 1 bytes), "cannot read the <noun>: <reason>".
/// The file is opened without blocking (a FIFO with no writer does not hang) and checked with
/// fstat on the descriptor read, so a file replaced between the check and the read is not read.
std::string read_input_file(const std::string& path, std::size_t limit, const InputKind& kind);

}  // namespace woven::io
