#include "woven/io/toml_reader.hpp"

#include <algorithm>

#include <cstdio>
#include <cstdlib>
#include <cmath>

#include "woven/common/error.hpp"

namespace woven::io {

namespace {

const char* type_name(const toml::node& n)
{
    switch (n.type()) {
    case toml::node_type::string: return "a string";
    case toml::node_type::integer: return "an integer";
    case toml::node_type::floating_point: return "a float";
    case toml::node_type::boolean: return "a boolean";
    case toml::node_type::array: return "an array";
    case toml::node_type::table: return "a table";
    case toml::node_type::date: return "a date";
    case toml::node_type::time: return "a time";
    case toml::node_type::date_time: return "a date-time";
    default: return "nothing";
    }
}

std::string join(const std::string& prefix, std::string_view key)
{
    return prefix.empty() ? std::string(key) : prefix + "." + std::string(key);
}

[[noreturn]] void limit_error(const std::string& source, int line, const std::string& what)
{
    throw InputError(source + ":" + std::to_string(line) + ": TOML: " + what);
}

}  // namespace

std::string num_str(double v)
{
    // The shortest %g form that reads back as v ("0.0001", "9.2e+18", "1e+300").
    char buf[64];
    const double a = std::abs(v);
    const int first = a >= 1 && a < 1e15 ? static_cast<int>(std::floor(std::log10(a))) + 1 : 1;
    for (int precision = first; precision <= 17; ++precision) {
        std::snprintf(buf, sizeof buf, "%.*g", precision, v);
        if (std::strtod(buf, nullptr) == v || !std::isfinite(v)) break;
    }
    return buf;
}

std::string vec_str(const Eigen::Vector3d& v)
{
    std::string s = "(";  // appended, as in Range::str
    s += num_str(v.x());
    s += ", ";
    s += num_str(v.y());
    s += ", ";
    s += num_str(v.z());
    s += ")";
    return s;
}

std::string Range::kind() const
{
    if (lo > 0 || (lo == 0 && lo_open)) return "a positive number";
    if (lo == 0) return "a non-negative number";
    return "a number";
}

std::string Range::str() const
{
    std::string s = lo_open ? "(" : "[";  // appended: "(" + std::string made GCC 12 warn falsely (-Wrestrict)
    s += num_str(lo);
    s += ", ";
    s += num_str(hi);
    s += "]";
    if (!unit.empty()) {
        s += ' ';
        s += unit;
    }
    return s;
}

void check_toml_limits(std::string_view text, const std::string& source)
{
    if (text.size() > kMaxTomlBytes)
        throw InputError(source, "file",
                         "expected a file of at most " + std::to_string(kMaxTomlBytes >> 20) + " MiB, got " +
                             std::to_string(text.size()) + " bytes");
    // A small scanner that knows strings and comments: outside them it counts the dots of one
    // key (reset at = , [ ] { } and newlines) and the depth of brackets and braces.
    enum class State { NORMAL, COMMENT, BASIC, LITERAL, ML_BASIC, ML_LITERAL };
    State st = State::NORMAL;
    int line = 1, dots = 0, depth = 0;
    const std::size_t n = text.size();
    auto starts = [&](std::size_t i, std::string_view s) { return text.substr(i, s.size()) == s; };
    for (std::size_t i = 0; i < n; ++i) {
        const char c = text[i];
        if (c == '\n') ++line;
        switch (st) {
        case State::COMMENT:
            if (c == '\n') st = State::NORMAL;
            break;
        case State::BASIC:
            if (c == '\\') ++i;  // an escaped character (a newline here is a syntax error anyway)
            else if (c == '"' || c == '\n') st = State::NORMAL;
            break;
        case State::LITERAL:
            if (c == '\'' || c == '\n') st = State::NORMAL;
            break;
        case State::ML_BASIC:
            if (c == '\\' && i + 1 < n) {
                if (text[i + 1] == '\n') ++line;
                ++i;
            } else if (starts(i, "\"\"\"")) {
                st = State::NORMAL;
                i += 2;
            }
            break;
        case State::ML_LITERAL:
            if (starts(i, "'''")) {
                st = State::NORMAL;
                i += 2;
            }
            break;
        case State::NORMAL:
            switch (c) {
            case '#': st = State::COMMENT; break;
            case '"':
                if (starts(i, "\"\"\"")) {
                    st = State::ML_BASIC;
                    i += 2;
                } else {
                    st = State::BASIC;
                }
                break;
            case '\'':
                if (starts(i, "'''")) {
                    st = State::ML_LITERAL;
                    i += 2;
                } else {
                    st = State::LITERAL;
                }
                break;
            case '.':
                if (++dots >= kMaxTomlKeyParts)
                    limit_error(source, line, "a key or table header of more than " +
                                                  std::to_string(kMaxTomlKeyParts) + " dotted parts");
                break;
            case '[':
            case '{':
                dots = 0;
                if (++depth > kMaxTomlNesting)
                    limit_error(source, line, "arrays, inline tables or headers nested more than " +
                                                  std::to_string(kMaxTomlNesting) + " deep");
                break;
            case ']':
            case '}':
                dots = 0;
                if (depth > 0) --depth;
                break;
            case '=':
            case ',':
            case '\n': dots = 0; break;
            default: break;
            }
            break;
        }
    }
}

toml::table parse_toml(std::string_view text, const std::string& source)
{
    check_toml_limits(text, source);
    try {
        return toml::parse(text, source);
    } catch (const toml::parse_error& e) {
        const auto& b = e.source().begin;
        throw InputError(source + ":" + std::to_string(b.line) + ":" + std::to_string(b.column) +
                         ": TOML syntax: " + printable(e.description(), 200));
    }
}

// ---------------------------------------------------------------------------------------------

std::string TomlTable::field(std::string_view key) const { return join(path_, key); }

const toml::node* TomlTable::node(std::string_view key) const
{
    const toml::node* n = table_->get(key);
    if (n) reader_->mark(n);
    return n;
}

std::vector<std::string> TomlTable::keys() const
{
    std::vector<std::pair<std::pair<int, int>, std::string>> at;
    for (const auto& [k, n] : *table_)
        at.push_back({{static_cast<int>(n.source().begin.line), static_cast<int>(n.source().begin.column)}, std::string(k.str())});
    std::stable_sort(at.begin(), at.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<std::string> out;
    for (auto& [pos, k] : at) out.push_back(std::move(k));
    return out;
}

void TomlTable::fail(std::string_view key, const std::string& expected) const { reader_->fail(field(key), expected); }

void TomlTable::fail_self(const std::string& expected) const { reader_->fail(path_, expected); }

void TomlTable::fail_at(const std::string& field, const std::string& expected) const { reader_->fail(field, expected); }

double TomlTable::to_number(const toml::node& n, const std::string& field, const Range& range) const
{
    double v;
    if (const auto* f = n.as_floating_point())
        v = f->get();
    else if (const auto* i = n.as_integer())
        v = static_cast<double>(i->get());
    else
        reader_->fail(field, "expected a number in " + range.str() + ", got " + type_name(n) + TomlReader::at(n));
    if (!std::isfinite(v)) reader_->fail(field, "expected a finite number in " + range.str() + ", got " + num_str(v) + TomlReader::at(n));
    if (!range.contains(v))
        reader_->fail(field, "expected " + range.kind() + " in " + range.str() + ", got " + num_str(v) + TomlReader::at(n));
    return v;
}

long long TomlTable::to_integer(const toml::node& n, const std::string& field, long long lo, long long hi) const
{
    const std::string expected = "expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
    long long v = 0;
    if (const auto* i = n.as_integer()) {
        v = i->get();
    } else if (const auto* f = n.as_floating_point();
               f && std::isfinite(f->get()) && f->get() == std::floor(f->get()) && std::abs(f->get()) < 9e15) {
        v = static_cast<long long>(f->get());
    } else {
        const std::string got = n.is_floating_point() ? num_str(n.as_floating_point()->get()) : type_name(n);
        reader_->fail(field, expected + ", got " + got + TomlReader::at(n));
    }
    if (v < lo || v > hi) reader_->fail(field, expected + ", got " + std::to_string(v) + TomlReader::at(n));
    return v;
}

std::optional<double> TomlTable::opt_number(std::string_view key, const Range& range) const
{
    const toml::node* n = node(key);
    if (!n) return std::nullopt;
    return to_number(*n, field(key), range);
}

double TomlTable::number(std::string_view key, const Range& range, std::optional<double> def) const
{
    if (auto v = opt_number(key, range)) return *v;
    if (!def) fail(key, "missing; expected a number in " + range.str());
    return *def;
}

long long TomlTable::integer(std::string_view key, long long lo, long long hi, std::optional<long long> def) const
{
    const toml::node* n = node(key);
    if (!n) {
        if (!def)
            fail(key, "missing; expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
        return *def;
    }
    return to_integer(*n, field(key), lo, hi);
}

std::string TomlTable::string(std::string_view key, std::optional<std::string> def) const
{
    const toml::node* n = node(key);
    if (!n) {
        if (!def) fail(key, "missing; expected a string");
        return *def;
    }
    if (const auto* s = n->as_string()) return s->get();
    fail(key, std::string("expected a string, got ") + type_name(*n) + TomlReader::at(*n));
}

std::string TomlTable::choice(std::string_view key, std::optional<std::string> def,
                              std::initializer_list<std::string_view> choices) const
{
    return choice(key, std::move(def), std::span<const std::string_view>(choices.begin(), choices.size()));
}

std::string TomlTable::choice(std::string_view key, std::optional<std::string> def, std::span<const std::string_view> choices) const
{
    std::string list;
    for (auto c : choices) list += (list.empty() ? "" : ", ") + std::string("\"") + std::string(c) + "\"";
    const toml::node* n = table_->get(key);
    if (!n && !def) fail(key, "missing; expected one of " + list);
    const std::string v = string(key, def);
    for (auto c : choices)
        if (c == v) return v;
    fail(key, "expected one of " + list + ", got \"" + printable(v) + "\"" + (n ? TomlReader::at(*n) : std::string()));
}

std::vector<double> TomlTable::fixed_numbers(std::string_view key, int count, const Range& range,
                                             const std::optional<std::vector<double>>& def) const
{
    const std::string what = "an array of " + std::to_string(count) + " numbers in " + range.str();
    const toml::node* n = node(key);
    if (!n) {
        if (!def) fail(key, "missing; expected " + what);
        return *def;
    }
    const toml::array* a = n->as_array();
    if (!a || static_cast<int>(a->size()) != count)
        fail(key, "expected " + what + ", got " + (a ? std::to_string(a->size()) + " values" : type_name(*n)) +
                      TomlReader::at(*n));
    std::vector<double> v(count);
    for (int k = 0; k < count; ++k) v[k] = to_number(*a->get(k), field(key), range);
    return v;
}

std::optional<std::vector<double>> TomlTable::numbers(std::string_view key, const Range& range) const
{
    const toml::node* n = node(key);
    if (!n) return std::nullopt;
    const toml::array* a = n->as_array();
    if (!a)
        fail(key, "expected an array of numbers in " + range.str() + ", got " + type_name(*n) + TomlReader::at(*n));
    std::vector<double> out;
    out.reserve(a->size());
    for (std::size_t k = 0; k < a->size(); ++k)
        out.push_back(to_number(*a->get(k), field(key) + "[" + std::to_string(k) + "]", range));
    return out;
}

std::optional<TomlTable> TomlTable::table(std::string_view key, bool required) const
{
    const toml::node* n = node(key);
    if (!n) {
        if (required) fail(key, "missing; expected a table [" + field(key) + "]");
        return std::nullopt;
    }
    const toml::table* t = n->as_table();
    if (!t) fail(key, "expected a table [" + field(key) + "], got " + type_name(*n) + TomlReader::at(*n));
    return TomlTable(reader_, t, field(key));
}

std::vector<TomlTable> TomlTable::tables(std::string_view key) const
{
    std::vector<TomlTable> out;
    const toml::node* n = node(key);
    if (!n) return out;
    const toml::array* a = n->as_array();
    if (!a) fail(key, "expected an array of tables ([[" + field(key) + "]]), got " + type_name(*n) + TomlReader::at(*n));
    for (std::size_t k = 0; k < a->size(); ++k) {
        const std::string name = field(key) + "[" + std::to_string(k + 1) + "]";
        const toml::table* t = a->get(k)->as_table();
        if (!t) reader_->fail(name, std::string("expected a table, got ") + type_name(*a->get(k)) + TomlReader::at(*a->get(k)));
        reader_->mark(t);
        out.push_back(TomlTable(reader_, t, name));
    }
    return out;
}

// ---------------------------------------------------------------------------------------------

TomlReader::TomlReader(std::string_view text, std::string source)
    : source_(std::move(source)), root_(parse_toml(text, source_))
{
}

TomlReader::TomlReader(toml::table root, std::string source) : source_(std::move(source)), root_(std::move(root)) {}

void TomlReader::fail(const std::string& field, const std::string& expected) const
{
    throw InputError(source_, field, expected);
}

std::string TomlReader::at(const toml::node& n)
{
    const auto& b = n.source().begin;
    return b.line > 0 ? " (line " + std::to_string(b.line) + ")" : std::string();
}

void TomlReader::collect_unknown(const toml::table& t, const std::string& path, std::vector<std::string>& out) const
{
    for (auto&& [k, v] : t) {
        const std::string field = join(path, k.str());
        if (!used(&v)) {
            const auto line = v.source().begin.line;
            out.push_back(source_ + (line > 0 ? ":" + std::to_string(line) : std::string()) + ": " + field +
                          ": unknown key, ignored");
            continue;
        }
        if (const toml::table* sub = v.as_table()) {
            collect_unknown(*sub, field, out);
        } else if (const toml::array* a = v.as_array()) {
            for (std::size_t e = 0; e < a->size(); ++e)
                if (const toml::table* sub = a->get(e)->as_table(); sub && used(sub))
                    collect_unknown(*sub, field + "[" + std::to_string(e + 1) + "]", out);
        }
    }
}

std::vector<std::string> TomlReader::unknown_keys() const
{
    std::vector<std::string> out;
    collect_unknown(root_, "", out);
    return out;
}

}  // namespace woven::io
