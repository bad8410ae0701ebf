// Number/list parsing and `$name` substitution.
#include <gtest/gtest.h>

#include "volguide/scene/scene_parameters.h"
#include "volguide/scene/xml_values.h"

using namespace volguide;

TEST(XmlValues, TokenizeCommasAndSpaces) {
    auto t = tokenize_list(" 1,2  3 ,\t4,,5 ");
    ASSERT_EQ(t.size(), 5u);
    EXPECT_EQ(t[0], "1");
    EXPECT_EQ(t[4], "5");
    EXPECT_TRUE(tokenize_list("  , ").empty());
}

TEST(XmlValues, StrictDoubles) {
    EXPECT_EQ(parse_double("1.5"), 1.5);
    EXPECT_EQ(parse_double(" -2e3 "), -2000.0);
    EXPECT_EQ(parse_double("+0.25"), 0.25);
    EXPECT_FALSE(parse_double("1.0x"));
    EXPECT_FALSE(parse_double(""));
    EXPECT_FALSE(parse_double("1 2"));
    EXPECT_FALSE(parse_double("nan"));
    EXPECT_FALSE(parse_double("NaN", true));
    EXPECT_FALSE(parse_double("inf"));
    EXPECT_TRUE(parse_double("inf", true));
    EXPECT_FALSE(parse_double("--1"));
}

TEST(XmlValues, StrictIntegersAndBooleans) {
    EXPECT_EQ(parse_int64("-17"), -17);
    EXPECT_FALSE(parse_int64("1.5"));
    EXPECT_FALSE(parse_int64("12abc"));
    EXPECT_FALSE(parse_int64("99999999999999999999"));
    EXPECT_EQ(parse_bool("True"), true);
    EXPECT_EQ(parse_bool("FALSE"), false);
    EXPECT_FALSE(parse_bool("yes"));
}

TEST(SceneParameters, Substitution) {
    SceneParameters p(std::map<std::string, std::string>{{"spp", "128"}});
    SourceLocation loc{"a.xml", 3};
    p.declare("res", "64", loc);
    p.declare("resx", "32", loc);
    p.declare("spp", "16", loc);
    p.declare("res", "999", loc);  // first declaration wins
    EXPECT_EQ(p.substitute("$res", loc), "64");
    EXPECT_EQ(p.substitute("$resx/$res", loc), "32/64");  // longest name wins
    EXPECT_EQ(p.substitute("img_$res.exr", loc), "img_64.exr");
    EXPECT_EQ(p.substitute("$spp", loc), "128");  // -D override
    EXPECT_EQ(p.substitute("cost \\$5", loc), "cost $5");
    EXPECT_THROW(p.substitute("$nope", loc), InputError);
    EXPECT_THROW(p.substitute("a $ b", loc), InputError);
    p.check_overrides(loc);
}

TEST(SceneParameters, UnknownOverrideIsAnError) {
    SceneParameters p(std::map<std::string, std::string>{{"typo", "1"}});
    p.declare("spp", "4", {"a.xml", 2});
    try {
        p.check_overrides({"a.xml", 0});
        FAIL();
    } catch (const InputError& e) {
        EXPECT_EQ(e.location().file, "a.xml");
        EXPECT_NE(e.message().find("typo"), std::string::npos);
    }
}

TEST(SceneParameters, DefaultsMayReferToOtherDefaults) {
    SceneParameters p;
    SourceLocation loc{"a.xml", 1};
    p.declare("base", "meshes", loc);
    p.declare("mesh", "$base/bunny.obj", loc);
    p.declare("loop", "x$loop", loc);
    EXPECT_EQ(p.substitute("$mesh", loc), "meshes/bunny.obj");
    EXPECT_THROW(p.substitute("$loop", loc), InputError);
}
