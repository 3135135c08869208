// The cloth grid as PLY (io/output.hpp), binary and ASCII, with per-vertex fields.
#include <cstring>
#include <sstream>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "woven/common/error.hpp"
#include "woven/io/output.hpp"

#include "io/grid_fixture.hpp"

using namespace woven;
using ::testing::HasSubstr;

namespace {

using woven::test::fields;
using woven::test::grid;
using woven::test::kNu;
using woven::test::kNv;

}  // namespace

TEST(ClothPlyFields, BinaryAndAsciiHoldTheSameValues)
{
    const Positions x = grid();
    const auto f = fields();
    const std::string bin = io::cloth_ply(x, kNu, kNv, f);
    const std::string asc = io::cloth_ply(x, kNu, kNv, f, io::PlyFormat::ASCII);
    EXPECT_EQ(bin.rfind("ply\nformat binary_little_endian 1.0\n", 0), 0u);
    EXPECT_EQ(asc.rfind("ply\nformat ascii 1.0\n", 0), 0u);
    for (const std::string* s : {&bin, &asc}) {
        EXPECT_THAT(*s, HasSubstr("property float strain_warp\nproperty float contact\n"));
        EXPECT_THAT(*s, HasSubstr("comment strain_warp unit: 1\n"));
        EXPECT_THAT(*s, HasSubstr("property double x\n"));
    }
    // Binary: header, then per vertex 3 doubles + 5 floats + 2 field floats, then per face
    // a uchar 3 and three int32.
    const std::size_t body = bin.find("end_header\n") + 11;
    const std::size_t vertex = 3 * 8 + 5 * 4 + 2 * 4, faces = 2 * (kNu - 1) * (kNv - 1);
    ASSERT_EQ(bin.size(), body + kNu * kNv * vertex + faces * 13);
    for (int p = 0; p < kNu * kNv; ++p) {
        double xyz[3];
        float rest[7];
        std::memcpy(xyz, bin.data() + body + p * vertex, sizeof xyz);
        std::memcpy(rest, bin.data() + body + p * vertex + sizeof xyz, sizeof rest);
        EXPECT_EQ(xyz[2], x[p].z());
        EXPECT_FLOAT_EQ(rest[5], static_cast<float>(f[0].values[p]));
        EXPECT_FLOAT_EQ(rest[6], static_cast<float>(f[1].values[p]));
    }
    // ASCII: the vertex lines end with the two fields.
    std::istringstream in(asc.substr(asc.find("end_header\n") + 11));
    for (int p = 0; p < kNu * kNv; ++p) {
        double v[10];
        for (double& c : v) in >> c;
        EXPECT_NEAR(v[8], f[0].values[p], 1e-9);
        EXPECT_EQ(v[9], f[1].values[p]);
    }
    auto bad = f;
    bad[1].values.push_back(0);
    EXPECT_THROW(io::cloth_ply(x, kNu, kNv, bad), InputError);
}
