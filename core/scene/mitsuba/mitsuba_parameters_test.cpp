// -D name=value (mitsuba_parameters.h): parsing, and the parameters written into the scene text.
#include "scene/mitsuba/mitsuba_parameters.h"

#include <gtest/gtest.h>

#include "scene/mitsuba/mitsuba_test_support.h"

namespace tessera {
namespace {

using testing::parse_xml;
using testing::sampler_scene;
using testing::xml_error;

std::string define_error(const std::string& text) {
  try {
    parse_mitsuba_define(text);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(MitsubaParameters, ParsesNameEqualsValue) {
  MitsubaParameter p = parse_mitsuba_define("spp=64");
  EXPECT_EQ(p.name, "spp");
  EXPECT_EQ(p.value, "64");
  p = parse_mitsuba_define("file=a=b.ply");
  EXPECT_EQ(p.name, "file");
  EXPECT_EQ(p.value, "a=b.ply");
  EXPECT_EQ(parse_mitsuba_define("empty_1=").value, "");
}

TEST(MitsubaParameters, BadDefinesNameWhatIsWrong) {
  EXPECT_EQ(define_error("spp"), "-D spp: write -D name=value");
  EXPECT_EQ(define_error("=4"), "-D =4: a parameter's name is letters, digits and '_' (as in $spp)");
  EXPECT_EQ(define_error("s-p=4"),
            "-D s-p=4: a parameter's name is letters, digits and '_' (as in $spp)");
  EXPECT_EQ(define_error("spp=$x"),
            "-D spp=$x: a value must not hold '$' (it is not substituted again)");
  try {
    parse_mitsuba_defines({"spp=4", "depth=2", "spp=8"});
    FAIL() << "a name given twice was accepted";
  } catch (const SceneError& e) {
    EXPECT_STREQ(e.what(), "-D spp given twice");
  }
}

TEST(MitsubaParameters, OverrideDefaultsAndKeepLineNumbers) {
  const std::string xml = sampler_scene("<default name=\"depth\" value=\"3\"/>");
  EXPECT_EQ(parse_xml(xml).render.max_depth, 3);
  const std::string given =
      with_mitsuba_parameters(xml, "test.xml", {{"depth", "5"}, {"unused", "a\"<&'b"}});
  EXPECT_EQ(parse_xml(given).render.max_depth, 5);
  // The root's start tag spans two lines; the defaults follow it on its last line, so every
  // later line keeps its number.
  EXPECT_NE(given.find("version=\"3.0.0\"><default name=\"depth\" value=\"5\"/><default name=\"unused\" "
                       "value=\"a&quot;&lt;&amp;'b\"/><default name=\"depth\" value=\"3\"/>\n"),
            std::string::npos)
      << given;
  const std::string bad = sampler_scene("", "<float name=\"bad\" value=\"1\"/>");
  const int bad_line = testing::line_of(bad, "<float name=\"bad\"");
  const std::string bad_given = with_mitsuba_parameters(bad, "test.xml", {{"depth", "5"}});
  EXPECT_NE(xml_error(bad_given).find("test.xml: line " + std::to_string(bad_line) + ":"),
            std::string::npos)
      << xml_error(bad_given);
}

TEST(MitsubaParameters, GiveAParameterTheSceneLeavesUndefined) {
  const std::string xml = sampler_scene("");
  EXPECT_NE(xml_error(xml).find("undefined parameter $depth (declare it with <default "
                                "name=\"depth\" value=\"...\"/>, or give -D depth=VALUE)"),
            std::string::npos)
      << xml_error(xml);
  EXPECT_EQ(parse_xml(with_mitsuba_parameters(xml, "test.xml", {{"depth", "7"}}))
                .render.max_depth,
            7);
  // A value that is not what the element takes is refused as if the file said it.
  EXPECT_NE(xml_error(with_mitsuba_parameters(xml, "test.xml", {{"depth", "deep"}}))
                .find("<integer name=\"max_depth\">"),
            std::string::npos);
}

TEST(MitsubaParameters, TheRootTagEndsOutsideQuotes) {
  EXPECT_EQ(with_mitsuba_parameters("<!-- <x> -->\n<scene a='>' b=\"/>\">\n</scene>", "a.xml",
                                    {{"n", "1"}}),
            "<!-- <x> -->\n<scene a='>' b=\"/>\"><default name=\"n\" value=\"1\"/>\n</scene>");
}

TEST(MitsubaParameters, EmptyRootAndNoParametersLeaveTheTextAlone) {
  EXPECT_EQ(with_mitsuba_parameters("<scene version=\"3.0.0\"/>", "a.xml", {{"a", "1"}}),
            "<scene version=\"3.0.0\"/>");
  EXPECT_EQ(with_mitsuba_parameters("<scene version=\"3.0.0\"></scene>", "a.xml", {}),
            "<scene version=\"3.0.0\"></scene>");
}

}  // namespace
}  // namespace tessera
