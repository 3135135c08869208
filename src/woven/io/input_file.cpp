#include "woven/io/input_file.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include "woven/common/error.hpp"

namespace woven::io {

namespace {

/// Closes a descriptor at the end of its scope.
struct Fd {
    int fd = -1;
    ~Fd()
    {
        if (fd >= 0) ::close(fd);
    }
};

std::string limit_text(std::size_t limit)
{
    if (limit >= (1u << 20) && limit % (1u << 20) == 0) return "at most " + std::to_string(limit >> 20) + " MiB";
    return "at most " + std::to_string(limit) + " bytes";
}

}  // namespace

std::string read_input_file(const std::string& path, std::size_t limit, const InputKind& kind)
{
    Fd f;
    do f.fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
    while (f.fd < 0 && errno == EINTR);
    if (f.fd < 0) {
        const int e = errno;
        if (e == ENOENT || e == ENOTDIR) throw InputError(path, "file", "no such " + kind.noun);
        if (e == EISDIR) throw InputError(path, "file", "is a directory; expected " + kind.expected);
        throw InputError(path, "file", "cannot read the " + kind.noun + ": " + std::strerror(e));
    }
    struct stat st {};
    if (::fstat(f.fd, &st) != 0) throw InputError(path, "file", "cannot read the " + kind.noun + ": " + std::strerror(errno));
    if (S_ISDIR(st.st_mode)) throw InputError(path, "file", "is a directory; expected " + kind.expected);
    if (!S_ISREG(st.st_mode))
        throw InputError(path, "file", "is not a regular file (a device, FIFO or socket); expected " + kind.expected);
    if (st.st_size >= 0 && static_cast<unsigned long long>(st.st_size) > limit)
        throw InputError(path, "file", "expected " + kind.expected + " of " + limit_text(limit) + ", got " +
                                           std::to_string(static_cast<long long>(st.st_size)) + " bytes");
    // A regular file: reads do not block. Stop at limit + 1 bytes whatever the size said (the
    // file may grow while it is read).
    std::string text;
    text.resize(std::min<std::size_t>(limit + 1, static_cast<std::size_t>(st.st_size) + 1));
    std::size_t n = 0;
    while (n <= limit) {
        if (n == text.size()) text.resize(std::min(limit + 1, 2 * text.size() + 4096));
        const ssize_t r = ::read(f.fd, text.data() + n, text.size() - n);
        if (r < 0) {
            if (errno == EINTR) continue;
            throw InputError(path, "file", "cannot read the " + kind.noun + ": " + std::strerror(errno));
        }
        if (r == 0) break;
        n += static_cast<std::size_t>(r);
    }
    if (n > limit)
        throw InputError(path, "file", "expected " + kind.expected + " of " + limit_text(limit) + ", got more (it grew while read)");
    text.resize(n);
    return text;
}

}  // namespace woven::io
