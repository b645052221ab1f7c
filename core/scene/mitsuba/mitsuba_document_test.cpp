// Reading Mitsuba XML: line numbers, version, <default> and $ substitution, <include>.
#include <gtest/gtest.h>

#include "scene/mitsuba/mitsuba_test_support.h"
#include "scene/mitsuba/mitsuba_xml_document.h"

namespace tessera {
namespace {

using testing::memory_reader;

MitsubaDocument read(const std::string& xml, std::map<std::string, std::string> files = {},
                     const std::string& file_name = "main.xml") {
  return read_mitsuba_document(xml, file_name, memory_reader(std::move(files)));
}

std::string read_error(const std::string& xml, std::map<std::string, std::string> files = {}) {
  try {
    read(xml, std::move(files));
  } catch (const SceneError& e) {
    return e.what();
  }
  return "(no error)";
}

/// The value attribute of the index-th child of the scene.
std::string value_of(const MitsubaDocument& d, size_t index) {
  const std::string* v = d.scene.children.at(index).attribute("value");
  return v ? *v : "(none)";
}

TEST(MitsubaDocument, ElementsKnowTheirFileAndLine) {
  MitsubaDocument d = read(
      "<?xml version=\"1.0\"?>\n<scene version=\"3.0.0\">\n  <!-- a comment -->\n"
      "  <bsdf type=\"diffuse\" id=\"white\">\n    <rgb name=\"reflectance\" value=\"1\"/>\n"
      "  </bsdf>\n</scene>\n");
  EXPECT_EQ(d.scene.line, 2);
  ASSERT_EQ(d.scene.children.size(), 1u);
  const MitsubaElement& bsdf = d.scene.children[0];
  EXPECT_EQ(bsdf.line, 4);
  EXPECT_EQ(bsdf.file, "main.xml");
  EXPECT_EQ(bsdf.children.at(0).line, 5);
  EXPECT_EQ(bsdf.label(), "<bsdf type=\"diffuse\" id=\"white\">");
  EXPECT_EQ(bsdf.where(), "main.xml: line 4: <bsdf type=\"diffuse\" id=\"white\">");
}

TEST(MitsubaDocument, LinesCountWithWindowsLineEnds) {
  MitsubaDocument d = read("<scene version=\"3.0.0\">\r\n\r\n<shape type=\"cube\"/>\r\n</scene>");
  EXPECT_EQ(d.scene.children.at(0).line, 3);
}

TEST(MitsubaDocument, MalformedXmlNamesTheLine) {
  EXPECT_EQ(read_error("<scene version=\"3.0.0\">\n<shape type=\"cube\">\n</scene>"),
            "main.xml: line 3: malformed XML: Start-end tags mismatch");
  EXPECT_EQ(read_error(""), "main.xml: line 1: malformed XML: No document element found");
}

TEST(MitsubaDocument, OnlyMitsuba3ScenesAreRead) {
  EXPECT_NO_THROW(read("<scene version=\"3.0.0\"/>"));
  EXPECT_NO_THROW(read("<scene version=\"3.5\"/>"));
  EXPECT_NO_THROW(read("<scene version=\"3\"/>"));
  EXPECT_NO_THROW(read("<scene version=\"2.1.0\"/>"));  // Mitsuba 3 reads 2.x files as they are
  EXPECT_EQ(read_error("<scene version=\"0.6.0\"/>"),
            "main.xml: line 1: <scene>: version \"0.6.0\": Tessera reads Mitsuba 3 scenes "
            "(version=\"3.x.y\" or \"2.x.y\"); upgrade older files with Mitsuba 3 first");
  EXPECT_NE(read_error("<scene version=\"3.x\"/>").find("version \"3.x\""), std::string::npos);
  EXPECT_NE(read_error("<scene/>").find("missing attribute \"version\""), std::string::npos);
  EXPECT_NE(read_error("<bsdf version=\"3.0.0\" type=\"diffuse\"/>").find("root element must be"),
            std::string::npos);
}

TEST(MitsubaDocument, DefaultsAreSubstitutedInLaterAttributes) {
  MitsubaDocument d = read(R"(<scene version="3.0.0">
    <default name="spp" value="64"/>
    <default name="color" value="0.1, 0.2"/>
    <integer name="a" value="$spp"/>
    <rgb name="b" value="$color, 0.3"/>
    <string name="c" value="$spp-$spp"/>
  </scene>)");
  ASSERT_EQ(d.scene.children.size(), 3u);  // <default>s leave no element
  EXPECT_EQ(value_of(d, 0), "64");
  EXPECT_EQ(value_of(d, 1), "0.1, 0.2, 0.3");
  EXPECT_EQ(value_of(d, 2), "64-64");
}

TEST(MitsubaDocument, TheFirstDefaultWins) {
  MitsubaDocument d = read(R"(<scene version="3.0.0">
    <default name="x" value="1"/>
    <default name="x" value="2"/>
    <float name="a" value="$x"/>
  </scene>)");
  EXPECT_EQ(value_of(d, 0), "1");
}

TEST(MitsubaDocument, LongerParameterNamesAreSubstitutedFirst) {
  MitsubaDocument d = read(R"(<scene version="3.0.0">
    <default name="res" value="A"/>
    <default name="resx" value="B"/>
    <string name="a" value="$resx $res $resy"/>
  </scene>)");
  EXPECT_EQ(value_of(d, 0), "B A Ay");
}

TEST(MitsubaDocument, DefaultsMaySubstituteOtherDefaults) {
  MitsubaDocument d = read(R"(<scene version="3.0.0">
    <default name="base" value="8"/>
    <default name="depth" value="$base"/>
    <integer name="a" value="$depth"/>
  </scene>)");
  EXPECT_EQ(value_of(d, 0), "8");
}

TEST(MitsubaDocument, EscapedDollarIsLiteral) {
  MitsubaDocument d = read(R"(<scene version="3.0.0">
    <default name="x" value="1"/>
    <string name="a" value="\$x costs $x"/>
  </scene>)");
  EXPECT_EQ(value_of(d, 0), "$x costs 1");
}

TEST(MitsubaDocument, UndefinedParametersAreErrors) {
  std::string xml =
      "<scene version=\"3.0.0\">\n  <integer name=\"spp\" value=\"$spp\"/>\n"
      "  <default name=\"spp\" value=\"4\"/>\n</scene>";
  // A <default> applies to what follows it, as in Mitsuba.
  EXPECT_EQ(read_error(xml),
            "main.xml: line 2: <integer name=\"spp\">: undefined parameter $spp "
            "(declare it with <default name=\"spp\" value=\"...\"/>, or give -D spp=VALUE)");
}

TEST(MitsubaDocument, DefaultNeedsNameAndValue) {
  EXPECT_NE(read_error("<scene version=\"3.0.0\"><default name=\"x\"/></scene>")
                .find("<default name=\"x\">: missing attribute \"value\""),
            std::string::npos);
  EXPECT_NE(read_error("<scene version=\"3.0.0\"><default name=\"\" value=\"1\"/></scene>")
                .find("name must not be empty"),
            std::string::npos);
  EXPECT_NE(read_error("<scene version=\"3.0.0\"><default name=\"a\" value=\"1\" b=\"\"/></scene>")
                .find("unexpected attribute \"b\""),
            std::string::npos);
}

TEST(MitsubaDocument, IncludedSceneContributesItsChildrenInPlace) {
  MitsubaDocument d = read(R"(<scene version="3.0.0">
    <float name="a" value="1"/>
    <include filename="parts/more.xml"/>
    <float name="d" value="4"/>
  </scene>)",
                           {{"parts/more.xml", R"(<scene version="3.0.0">
  <float name="b" value="2"/>
  <float name="c" value="3"/>
</scene>)"}});
  ASSERT_EQ(d.scene.children.size(), 4u);
  EXPECT_EQ(value_of(d, 1), "2");
  EXPECT_EQ(value_of(d, 2), "3");
  EXPECT_EQ(value_of(d, 3), "4");
  EXPECT_EQ(d.scene.children[1].file, "parts/more.xml");
  EXPECT_EQ(d.scene.children[1].folder, "parts/");
  EXPECT_EQ(d.scene.children[1].line, 2);
  EXPECT_EQ(d.files_read, std::vector<std::string>{"parts/more.xml"});
}

TEST(MitsubaDocument, IncludedSingleElementIsItself) {
  MitsubaDocument d = read(R"(<scene version="3.0.0"><include filename="white.xml"/></scene>)",
                           {{"white.xml", R"(<bsdf version="3.0.0" type="diffuse" id="white"/>)"}});
  ASSERT_EQ(d.scene.children.size(), 1u);
  EXPECT_EQ(d.scene.children[0].tag, "bsdf");
  EXPECT_EQ(*d.scene.children[0].attribute("id"), "white");
}

TEST(MitsubaDocument, IncludesShareParametersAndResolveRelativeToTheirFile) {
  MitsubaDocument d = read(R"(<scene version="3.0.0">
    <default name="x" value="7"/>
    <include filename="a/one.xml"/>
    <float name="after" value="$y"/>
  </scene>)",
                           {{"a/one.xml", R"(<scene version="3.0.0">
    <default name="y" value="8"/>
    <include filename="b/two.xml"/>
  </scene>)"},
                            {"a/b/two.xml", R"(<scene version="3.0.0">
    <float name="x" value="$x"/>
  </scene>)"}});
  ASSERT_EQ(d.scene.children.size(), 2u);
  EXPECT_EQ(value_of(d, 0), "7");
  EXPECT_EQ(d.scene.children[0].file, "a/b/two.xml");
  EXPECT_EQ(value_of(d, 1), "8");
  EXPECT_EQ(d.files_read, (std::vector<std::string>{"a/one.xml", "a/b/two.xml"}));
}

TEST(MitsubaDocument, IncludesStayInsideTheBundle) {
  std::string xml = "<scene version=\"3.0.0\">\n<include filename=\"../secret.xml\"/>\n</scene>";
  EXPECT_EQ(read_error(xml),
            "main.xml: line 2: <include>: \"../secret.xml\" leaves the bundle root (the bundle "
            "root): every file a scene names must be inside it (render, convert and submit take "
            "--root DIR to widen it)");
  EXPECT_NE(read_error("<scene version=\"3.0.0\"><include filename=\"/etc/x.xml\"/></scene>")
                .find("<include>: \"/etc/x.xml\" is absolute"),
            std::string::npos);
  // From an included file in a subfolder, ".." may climb back to the root, not above it.
  MitsubaDocument d = read("<scene version=\"3.0.0\"><include filename=\"a/one.xml\"/></scene>",
                           {{"a/one.xml",
                             "<scene version=\"3.0.0\"><include filename=\"../b.xml\"/>"
                             "</scene>"},
                            {"b.xml", "<scene version=\"3.0.0\"><float name=\"x\" value=\"1\"/>"
                                      "</scene>"}});
  EXPECT_EQ(d.files_read, (std::vector<std::string>{"a/one.xml", "b.xml"}));
  EXPECT_NE(read_error("<scene version=\"3.0.0\"><include filename=\"a/one.xml\"/></scene>",
                       {{"a/one.xml",
                         "<scene version=\"3.0.0\"><include filename=\"../../b.xml\"/>"
                         "</scene>"}})
                .find("a/one.xml: line 1: <include>: \"../../b.xml\" leaves the bundle root"),
            std::string::npos);
}

TEST(MitsubaDocument, PathElementsAreSearchedFirst) {
  // Mitsuba's FileResolver: <path> folders, the latest first, then the scene's folder. An
  // include looks in the including file's folder before them.
  MitsubaDocument d = read(R"(<scene version="3.0.0">
    <path value="common"/>
    <path value="../shared"/>
    <include filename="parts.xml"/>
  </scene>)",
                           {{"scene/common/parts.xml", "<scene version=\"3.0.0\"/>"},
                            {"shared/parts.xml", "<scene version=\"3.0.0\"/>"}},
                           "scene/main.xml");
  EXPECT_EQ(d.search_folders,
            (std::vector<std::string>{"shared/", "scene/common/", "scene/"}));
  EXPECT_EQ(d.files_read, (std::vector<std::string>{"shared/parts.xml"}));
  EXPECT_NE(read_error("<scene version=\"3.0.0\"><shape type=\"cube\"><path value=\"x\"/>"
                       "</shape></scene>")
                .find("a <path> must be a child of the <scene>"),
            std::string::npos);
  EXPECT_NE(read_error("<scene version=\"3.0.0\"><path value=\"x\"/>"
                       "<include filename=\"gone.xml\"/></scene>")
                .find("<include>: \"gone.xml\" is in none of the folders searched ((the root), "
                      "x/; first: gone.xml: no such file"),
            std::string::npos);
}

TEST(MitsubaDocument, MissingIncludeNamesTheLine) {
  EXPECT_EQ(read_error("<scene version=\"3.0.0\">\n\n<include filename=\"gone.xml\"/></scene>"),
            "main.xml: line 3: <include>: gone.xml: no such file in the scene's folder");
}

TEST(MitsubaDocument, ErrorsInIncludedFilesNameThatFile) {
  EXPECT_EQ(read_error("<scene version=\"3.0.0\"><include filename=\"bad.xml\"/></scene>",
                       {{"bad.xml",
                         "<scene version=\"3.0.0\">\n<float name=\"a\" value=\"$q\"/>"
                         "</scene>"}}),
            "bad.xml: line 2: <float name=\"a\">: undefined parameter $q (declare it with "
            "<default name=\"q\" value=\"...\"/>, or give -D q=VALUE)");
  EXPECT_EQ(read_error("<scene version=\"3.0.0\"><include filename=\"bad.xml\"/></scene>",
                       {{"bad.xml", "<scene version=\"3.0.0\">\n\n<float></scene>"}}),
            "bad.xml: line 3: malformed XML: Start-end tags mismatch");
}

TEST(MitsubaDocument, IncludeCyclesAreRefused) {
  std::string error = read_error("<scene version=\"3.0.0\"><include filename=\"a.xml\"/></scene>",
                                 {{"a.xml",
                                   "<scene version=\"3.0.0\"><include filename=\"b.xml\"/>"
                                   "</scene>"},
                                  {"b.xml",
                                   "<scene version=\"3.0.0\"><include filename=\"a.xml\"/>"
                                   "</scene>"}});
  EXPECT_EQ(error, "b.xml: line 1: <include>: \"a.xml\" includes itself");
  EXPECT_NE(read_error("<scene version=\"3.0.0\"><include filename=\"main.xml\"/></scene>",
                       {{"main.xml", "<scene version=\"3.0.0\"/>"}})
                .find("includes itself"),
            std::string::npos);
}

TEST(MitsubaDocument, IncludesNestAtMostSixteenDeep) {
  std::map<std::string, std::string> files;
  for (int i = 0; i < 20; ++i) {
    files["f" + std::to_string(i) + ".xml"] = "<scene version=\"3.0.0\"><include filename=\"f" +
                                              std::to_string(i + 1) + ".xml\"/></scene>";
  }
  files["f20.xml"] = "<scene version=\"3.0.0\"/>";
  EXPECT_NE(read_error("<scene version=\"3.0.0\"><include filename=\"f0.xml\"/></scene>", files)
                .find("includes nest more than 16 deep"),
            std::string::npos);
}

TEST(MitsubaDocument, DeepNestingIsRefusedNotRecursedInto) {
  std::string xml = "<scene version=\"3.0.0\">";
  for (int i = 0; i < 100000; ++i) xml += "<a>";
  for (int i = 0; i < 100000; ++i) xml += "</a>";
  xml += "</scene>";
  EXPECT_NE(read_error(xml).find("elements nested more than 64 deep"), std::string::npos);
}

TEST(MitsubaDocument, IncludeTakesOnlyFilename) {
  EXPECT_NE(read_error("<scene version=\"3.0.0\"><include filename=\"a.xml\" x=\"1\"/></scene>",
                       {{"a.xml", "<scene version=\"3.0.0\"/>"}})
                .find("unexpected attribute \"x\""),
            std::string::npos);
}

TEST(MitsubaDocument, IncludedFilesNeedAVersion) {
  EXPECT_NE(read_error("<scene version=\"3.0.0\"><include filename=\"a.xml\"/></scene>",
                       {{"a.xml", "<scene/>"}})
                .find("a.xml: line 1: <scene>: missing attribute \"version\""),
            std::string::npos);
}

}  // namespace
}  // namespace tessera
