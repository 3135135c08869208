#pragma once
// Project exceptions. Only the cli catches them: InputError -> exit 2, RuntimeError -> exit 1.
#include <cstdio>
#include <stdexcept>
#include <string>
#include <string_view>

namespace woven {

/// `s` with each NUL byte written as \x00: what() is a C string, so a NUL (in a name a caller
/// gave) would cut the message there.
inline std::string without_nul(std::string s)
{
    for (std::size_t k = s.find('\0'); k != std::string::npos; k = s.find('\0', k + 4)) s.replace(k, 1, "\\x00");
    return s;
}

/// Text from an input made safe for a one-line message: control characters (newlines included)
/// become "\xNN", and it is cut at `max_length` characters ("...").
inline std::string printable(std::string_view text, std::size_t max_length = 80)
{
    std::string out;
    for (std::size_t i = 0; i < text.size(); ++i) {
        if (out.size() >= max_length) return out + "...";
        const auto c = static_cast<unsigned char>(text[i]);
        if (c < 0x20 || c == 0x7f) {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\x%02x", c);
            out += buf;
        } else {
            out += static_cast<char>(c);
        }
    }
    return out;
}

/// Bad input: a malformed or inconsistent file, a value out of range, a bad option.
/// The message is one line: "<source>: <field>: <what is expected>".
class InputError : public std::runtime_error {
public:
    InputError(const std::string& source, const std::string& field, const std::string& expected)
        : std::runtime_error(compose(source, field, expected)), source_(source), field_(field)
    {
    }
    explicit InputError(const std::string& message) : std::runtime_error(without_nul(message)) { }
    const std::string& source() const { return source_; }
    const std::string& field() const { return field_; }

private:
    static std::string compose(const std::string& source, const std::string& field, const std::string& expected)
    {
        std::string m = source.empty() ? std::string() : source + ": ";
        if (!field.empty()) m += field + ": ";
        return without_nul(m + expected);
    }
    std::string source_, field_;
};

/// A failure while running on valid input (I/O error, solver breakdown).
class RuntimeError : public std::runtime_error {
public:
    explicit RuntimeError(const std::string& message) : std::runtime_error(without_nul(message)) { }
    explicit RuntimeError(const char* message) : std::runtime_error(message) { }
};

}  // namespace woven
