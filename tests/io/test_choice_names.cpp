// The names of each choice (common/choice.hpp): one table per enum, in the module that owns it;
// printing, parsing and the scene reader's lists read that table.
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "woven/common/choice.hpp"
#include "woven/common/error.hpp"
#include "woven/common/units.hpp"
#include "woven/io/toml_reader.hpp"
#include "woven/model/cloth_model.hpp"
#include "woven/sim/drape.hpp"

namespace woven {
namespace {

/// Every name maps back to its value, names and values are unique, and `count` values are listed.
template <class E, std::size_t N>
void expect_one_to_one(const std::array<Named<E>, N>& table, std::size_t count)
{
    EXPECT_EQ(N, count);
    std::set<std::string> names;
    std::set<E> values;
    for (const Named<E>& n : table) {
        names.insert(n.name);
        values.insert(n.value);
        EXPECT_EQ(value_named(table, n.name), n.value) << n.name;
        EXPECT_STREQ(name_of(table, n.value), n.name);
    }
    EXPECT_EQ(names.size(), N);
    EXPECT_EQ(values.size(), N);
    EXPECT_FALSE(value_named(table, "no-such-name"));
    EXPECT_FALSE(value_named(table, ""));
}

TEST(ChoiceNames, EachTableIsOneToOneOverItsEnum)
{
    expect_one_to_one(model::kHysteresisNames, 2);
    expect_one_to_one(model::kShearLawNames, 2);
    expect_one_to_one(model::kDiscretizationNames, 2);
    expect_one_to_one(units::kGramForceNames, 2);
    expect_one_to_one(sim::kSolverKindNames, 2);
}

TEST(ChoiceNames, ToStringAndFromStringReadTheTables)
{
    EXPECT_STREQ(model::to_string(model::Hysteresis::FRICTION), "friction");
    EXPECT_STREQ(model::to_string(model::Hysteresis::LOADING_BRANCH), "loading-branch");
    EXPECT_STREQ(model::to_string(model::ShearLaw::DEEMBEDDED), "deembedded");
    EXPECT_STREQ(model::to_string(model::Discretization::CONVERGENT), "convergent");
    EXPECT_STREQ(units::to_string(units::GramForce::STANDARD), "standard");
    EXPECT_STREQ(sim::to_string(sim::SolverKind::PAPER), "paper");
    EXPECT_EQ(sim::solver_kind_from_string("fast"), sim::SolverKind::FAST);
    EXPECT_FALSE(sim::solver_kind_from_string("Fast"));
}

TEST(ChoiceNames, TomlChoiceReadsAValueByNameKeepsTheDefaultAndListsTheNamesInErrors)
{
    const io::TomlReader r("h = \"friction\"\nbad = \"slip\"\n", "c.toml");
    const io::TomlTable root = r.root();
    EXPECT_EQ(root.choice("h", model::Hysteresis::LOADING_BRANCH, model::kHysteresisNames), model::Hysteresis::FRICTION);
    EXPECT_EQ(root.choice("absent", model::Hysteresis::FRICTION, model::kHysteresisNames), model::Hysteresis::FRICTION);
    try {
        root.choice("bad", model::Hysteresis::LOADING_BRANCH, model::kHysteresisNames);
        FAIL();
    } catch (const InputError& e) {
        EXPECT_STREQ(e.what(), "c.toml: bad: expected one of \"loading-branch\", \"friction\", got \"slip\" (line 2)");
    }
}

}  // namespace
}  // namespace woven
