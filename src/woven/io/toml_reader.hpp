#pragma once
// The one TOML reader of io: parsing with input limits, typed getters that name the dotted field
// in errors ("<source>: <field>: <what is expected>"), ranges for every number, and used-key
// bookkeeping: every key a getter reads is marked, and the keys never read are reported as
// warnings "<source>:<line>: <field>: unknown key, ignored". Scene and fabric files use it.
#include <array>
#include <cstddef>
#include <initializer_list>
#include <memory>
#include <optional>
#include <set>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json_fwd.hpp>
#include <toml++/toml.h>

#include "woven/common/choice.hpp"
#include "woven/common/error.hpp"

namespace woven::io {

/// Input limits checked before toml++ sees the text (its parser and destructor recurse once per
/// dotted key part and nesting level: 40,000 parts overflow the stack).
inline constexpr std::size_t kMaxTomlBytes = 8u << 20;  ///< 8 MiB
inline constexpr int kMaxTomlKeyParts = 32;             ///< dotted parts of one key or table header
inline constexpr int kMaxTomlNesting = 32;              ///< nested arrays / inline tables / headers

/// Checks the limits above; InputError "<source>:<line>: TOML: ..." when one is exceeded.
void check_toml_limits(std::string_view text, const std::string& source);

/// check_toml_limits, then toml++; a syntax error is InputError "<source>:<line>:<col>: TOML syntax: ...".
toml::table parse_toml(std::string_view text, const std::string& source);

/// A closed or half-open interval of allowed values for a number.
struct Range {
    double lo;
    double hi;
    bool lo_open = false;  ///< true: lo itself is excluded ("> 0")
    std::string unit;      ///< printed after the interval ("m", "deg"); may be empty

    bool contains(double v) const { return (lo_open ? v > lo : v >= lo) && v <= hi; }
    /// "a positive number", "a non-negative number" or "a number"
    std::string kind() const;
    /// "(0, 100] m"
    std::string str() const;
};

/// Shortest round-trip text of a number ("1e+300", "0.5").
std::string num_str(double v);
/// "(x, y, z)" of num_str's texts (messages about a point or a vector of an input file).
std::string vec_str(const Eigen::Vector3d& v);

/// A TOML document of a tree of values (values.cpp): objects become tables, arrays arrays,
/// strings, integers, floats and booleans themselves. InputError "<source>: <field>: ..." for a
/// null, an integer beyond 64 bits, a root that is not an object, or nesting beyond
/// kMaxTomlNesting. Non-finite floats are kept, for the readers' own checks to refuse.
toml::table table_from_values(const nlohmann::json& values, const std::string& source);

class TomlReader;

/// One table of the document, as seen through its reader. Getters mark the key used; a key
/// that is absent gives the default or, when the default is std::nullopt, "missing; expected ...".
class TomlTable {
public:
    /// The dotted field of a key of this table ("cloth.size_m", "obstacle[2].radius_m").
    std::string field(std::string_view key) const;
    /// The table's own field ("" for the root).
    const std::string& path() const { return path_; }
    /// True when the key is present (does not mark it used).
    bool has(std::string_view key) const { return table_->contains(key); }
    /// The node of a key (marked used), or nullptr.
    const toml::node* node(std::string_view key) const;
    /// The table's keys in the order they are written in the file (does not mark them used).
    std::vector<std::string> keys() const;

    [[noreturn]] void fail(std::string_view key, const std::string& expected) const;
    /// Fails naming the table itself.
    [[noreturn]] void fail_self(const std::string& expected) const;
    /// Fails naming `field` (a full dotted field, such as an array element "axes.seed[2]").
    [[noreturn]] void fail_at(const std::string& field, const std::string& expected) const;

    double number(std::string_view key, const Range& range, std::optional<double> def) const;
    std::optional<double> opt_number(std::string_view key, const Range& range) const;
    long long integer(std::string_view key, long long lo, long long hi, std::optional<long long> def) const;
    std::string string(std::string_view key, std::optional<std::string> def) const;
    /// A string from a fixed set.
    std::string choice(std::string_view key, std::optional<std::string> def,
                       std::initializer_list<std::string_view> choices) const;
    std::string choice(std::string_view key, std::optional<std::string> def, std::span<const std::string_view> choices) const;
    /// A value of an enum by its name in the enum's table (common/choice.hpp); `def` when absent.
    template <class E, std::size_t N>
    E choice(std::string_view key, E def, const std::array<Named<E>, N>& table) const
    {
        std::array<std::string_view, N> names;
        for (std::size_t k = 0; k < N; ++k) names[k] = table[k].name;
        return *value_named(table, choice(key, std::string(name_of(table, def)), std::span<const std::string_view>(names)));
    }
    /// A fixed-length array of numbers, each in `range`.
    template <int N>
    Eigen::Matrix<double, N, 1> vec(std::string_view key, const Range& range,
                                    std::optional<Eigen::Matrix<double, N, 1>> def) const
    {
        std::optional<std::vector<double>> d;
        if (def) d = std::vector<double>(def->data(), def->data() + N);
        const std::vector<double> v = fixed_numbers(key, N, range, d);
        return Eigen::Map<const Eigen::Matrix<double, N, 1>>(v.data());
    }
    /// An array of numbers of any length (absent: nullopt), each in `range`.
    std::optional<std::vector<double>> numbers(std::string_view key, const Range& range) const;
    /// A sub-table (absent: nullopt, or "missing" when required).
    std::optional<TomlTable> table(std::string_view key, bool required = false) const;
    /// An array of tables ([[key]]); elements are named "<key>[1]", "<key>[2]", ...
    std::vector<TomlTable> tables(std::string_view key) const;

    /// A number node's value (integer or float), finite and in range; `field` names it.
    double to_number(const toml::node& n, const std::string& field, const Range& range) const;
    /// An integer node's value in [lo, hi] (a float with an integral value is accepted).
    long long to_integer(const toml::node& n, const std::string& field, long long lo, long long hi) const;

private:
    friend class TomlReader;
    TomlTable(const TomlReader* reader, const toml::table* table, std::string path)
        : reader_(reader), table_(table), path_(std::move(path))
    {
    }
    std::vector<double> fixed_numbers(std::string_view key, int n, const Range& range,
                                      const std::optional<std::vector<double>>& def) const;

    const TomlReader* reader_;
    const toml::table* table_;
    std::string path_;
};

/// A parsed document, its source name and the record of the nodes read.
class TomlReader {
public:
    /// Parses `text` (parse_toml); `source` names the file in every message.
    TomlReader(std::string_view text, std::string source);
    /// A document built in memory (io/values.hpp: values a Python caller passes); its nodes have
    /// no line, so messages name the field alone.
    TomlReader(toml::table root, std::string source);
    TomlReader(const TomlReader&) = delete;
    TomlReader& operator=(const TomlReader&) = delete;

    const std::string& source() const { return source_; }
    TomlTable root() const { return TomlTable(this, &root_, ""); }
    /// True when the document has no key at all.
    bool empty() const { return root_.empty(); }

    /// Throws InputError(source, field, expected).
    [[noreturn]] void fail(const std::string& field, const std::string& expected) const;

    /// One warning per key never read inside a table that was read:
    /// "<source>:<line>: <field>: unknown key, ignored".
    std::vector<std::string> unknown_keys() const;

    /// " (line N)" for a node with a known position, else "".
    static std::string at(const toml::node& n);

private:
    friend class TomlTable;
    void mark(const toml::node* n) const { used_.insert(n); }
    bool used(const toml::node* n) const { return used_.count(n) > 0; }
    void collect_unknown(const toml::table& t, const std::string& path, std::vector<std::string>& out) const;

    std::string source_;
    toml::table root_;
    mutable std::set<const toml::node*> used_;
};

}  // namespace woven::io
