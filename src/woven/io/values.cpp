// A tree of values (nlohmann::json) as the TOML document it stands for (values.hpp).
#include <cstdint>
#include <limits>
#include <string>

#include <nlohmann/json.hpp>

#include "woven/common/error.hpp"
#include "woven/io/toml_reader.hpp"

namespace woven::io {

namespace {

std::string child(const std::string& field, const std::string& key)
{
    return field.empty() ? printable(key) : field + "." + printable(key);
}

/// One value as a TOML node; `field` names it in errors, `depth` counts the enclosing tables and
/// arrays (at most kMaxTomlNesting, as in a file).
std::unique_ptr<toml::node> node_from_value(const nlohmann::json& v, const std::string& source, const std::string& field,
                                            int depth)
{
    using T = nlohmann::json::value_t;
    if ((v.is_object() || v.is_array()) && depth >= kMaxTomlNesting)
        throw InputError(source, field, "nested more than " + std::to_string(kMaxTomlNesting) + " levels deep");
    switch (v.type()) {
    case T::object: {
        auto t = std::make_unique<toml::table>();
        for (const auto& [key, value] : v.items()) t->insert(key, std::move(*node_from_value(value, source, child(field, key), depth + 1)));
        return t;
    }
    case T::array: {
        auto a = std::make_unique<toml::array>();
        for (std::size_t k = 0; k < v.size(); ++k)
            a->push_back(std::move(*node_from_value(v[k], source, field + "[" + std::to_string(k + 1) + "]", depth + 1)));
        return a;
    }
    case T::string: return std::make_unique<toml::value<std::string>>(v.get<std::string>());
    case T::boolean: return std::make_unique<toml::value<bool>>(v.get<bool>());
    case T::number_integer: return std::make_unique<toml::value<std::int64_t>>(v.get<std::int64_t>());
    case T::number_unsigned: {
        const std::uint64_t u = v.get<std::uint64_t>();
        if (u > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()))
            throw InputError(source, field, "expected an integer within 64 bits (at most 9223372036854775807), got " + std::to_string(u));
        return std::make_unique<toml::value<std::int64_t>>(static_cast<std::int64_t>(u));
    }
    case T::number_float: return std::make_unique<toml::value<double>>(v.get<double>());
    case T::null: throw InputError(source, field, "expected a value, got None (leave the key out for its default)");
    default: throw InputError(source, field, "expected a string, number, boolean, list or dict");
    }
}

}  // namespace

toml::table table_from_values(const nlohmann::json& values, const std::string& source)
{
    if (!values.is_object()) throw InputError(source, "", "expected a dict of the file's keys");
    std::unique_ptr<toml::node> root = node_from_value(values, source, "", 0);
    return std::move(*root->as_table());
}

}  // namespace woven::io
