#pragma once
// A choice among the values of an enum, by name: each enum a user can choose (on the command
// line, in a scene file, in a sweep) has one table of its names, in the module that owns the
// enum; printing, parsing and the listing of the names in errors all read that table.
#include <array>
#include <cstddef>
#include <optional>
#include <string_view>
#include <vector>

namespace woven {

/// One value of an enum and its name.
template <class E>
struct Named {
    E value;
    const char* name;
};

/// The name of `value` in `table` (nullptr when absent: every table lists all its enum's values).
template <class E, std::size_t N>
constexpr const char* name_of(const std::array<Named<E>, N>& table, E value)
{
    for (const Named<E>& n : table)
        if (n.value == value) return n.name;
    return nullptr;
}

/// The value named `name` in `table`; nullopt for any other name.
template <class E, std::size_t N>
constexpr std::optional<E> value_named(const std::array<Named<E>, N>& table, std::string_view name)
{
    for (const Named<E>& n : table)
        if (name == n.name) return n.value;
    return std::nullopt;
}

/// The names of `table`, in its order.
template <class E, std::size_t N>
std::vector<const char*> names_of(const std::array<Named<E>, N>& table)
{
    std::vector<const char*> names;
    for (const Named<E>& n : table) names.push_back(n.name);
    return names;
}

}  // namespace woven
