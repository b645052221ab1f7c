// Mitsuba sensors' film, reconstruction filter and sampler.
#include <gtest/gtest.h>

#include <cmath>

#include <glm/geometric.hpp>

#include "scene/mitsuba/mitsuba_sensor_test_support.h"
#include "scene/mitsuba/mitsuba_test_support.h"

namespace tessera {
namespace {

using testing::sensor;
using testing::sensor_error;
using testing::with_sensor;

TEST(MitsubaFilm, SizeAndAcceptedFormats) {
  Scene s = with_sensor(sensor(R"(<float name="fov" value="30"/>)", "perspective",
                               R"(<film type="hdrfilm"><integer name="width" value="320"/>
      <integer name="height" value="200"/><string name="pixel_format" value="rgba"/>
      <string name="component_format" value="float16"/><string name="file_format" value="openexr"/>
      <boolean name="sample_border" value="true"/><integer name="crop_offset_x" value="0"/>
      <integer name="crop_width" value="320"/><rfilter type="box"/></film>)"));
  EXPECT_EQ(s.film.width, 320);
  EXPECT_EQ(s.film.height, 200);
  Scene defaults = with_sensor(sensor(R"(<float name="fov" value="30"/>)"));
  EXPECT_EQ(defaults.film.width, 768);  // Mitsuba's hdrfilm defaults
  EXPECT_EQ(defaults.film.height, 576);
}

TEST(MitsubaFilm, BooleansMitsubaIgnoresAreAccepted) {
  auto film_of = [](const std::string& inside) {
    return sensor(R"(<float name="fov" value="30"/>)", "perspective",
                  "<film type=\"hdrfilm\"><integer name=\"width\" value=\"32\"/>" + inside +
                      "<rfilter type=\"box\"/></film>");
  };
  const Scene plain = with_sensor(film_of(""));
  for (const char* value : {"true", "false"}) {
    const Scene s = with_sensor(film_of(std::string("<boolean name=\"banner\" value=\"") + value +
                                        "\"/><boolean name=\"compensate\" value=\"" + value +
                                        "\"/>"));
    EXPECT_EQ(s.film.width, plain.film.width);
    EXPECT_EQ(s.film.height, plain.film.height);
    EXPECT_EQ(s.film.filter.kind, plain.film.filter.kind);
  }
  // Still booleans: anything else is refused.
  EXPECT_NE(sensor_error(film_of(R"(<boolean name="banner" value="maybe"/>)")).find("banner"),
            std::string::npos);
  // Mitsuba 0.6's high_quality_edges, which Mitsuba 3 refuses as well.
  EXPECT_NE(sensor_error(film_of(R"(<boolean name="high_quality_edges" value="true"/>)"))
                .find("<boolean name=\"high_quality_edges\">: Mitsuba 0.6's parameter, which "
                      "Mitsuba 3 refuses too"),
            std::string::npos);
}

TEST(MitsubaFilm, ReconstructionFilters) {
  auto filter_of = [](const std::string& film) {
    return with_sensor(sensor(R"(<float name="fov" value="30"/>)", "perspective", film))
        .film.filter;
  };
  PixelFilter box = filter_of(R"(<film type="hdrfilm"><rfilter type="box"/></film>)");
  EXPECT_EQ(box.kind, FilterKind::box);
  EXPECT_EQ(box.radius, 0.5);
  PixelFilter tent = filter_of(R"(<film type="hdrfilm"><rfilter type="tent"/></film>)");
  EXPECT_EQ(tent.kind, FilterKind::tent);
  EXPECT_EQ(tent.radius, 1.0);
  PixelFilter gauss = filter_of(R"(<film type="hdrfilm"><rfilter type="gaussian">
      <float name="stddev" value="0.25"/></rfilter></film>)");
  EXPECT_EQ(gauss.kind, FilterKind::gaussian);
  EXPECT_EQ(gauss.stddev, 0.25);
  EXPECT_EQ(gauss.radius, 1.0);  // Mitsuba truncates at 4 stddev
  PixelFilter mitchell = filter_of(R"(<film type="hdrfilm"><rfilter type="mitchell"/></film>)");
  EXPECT_EQ(mitchell.kind, FilterKind::mitchell);
  EXPECT_EQ(mitchell.radius, 2.0);
  EXPECT_EQ(mitchell.b, 1.0 / 3);
  EXPECT_EQ(mitchell.c, 1.0 / 3);
  mitchell = filter_of(R"(<film type="hdrfilm"><rfilter type="mitchell">
      <float name="B" value="0.5"/><float name="C" value="0.25"/></rfilter></film>)");
  EXPECT_EQ(mitchell.b, 0.5);
  EXPECT_EQ(mitchell.c, 0.25);
  PixelFilter catmullrom = filter_of(R"(<film type="hdrfilm"><rfilter type="catmullrom"/></film>)");
  EXPECT_EQ(catmullrom.kind, FilterKind::mitchell);
  EXPECT_EQ(catmullrom.b, 0.0);
  EXPECT_EQ(catmullrom.c, 0.5);
  PixelFilter lanczos = filter_of(R"(<film type="hdrfilm"><rfilter type="lanczos"/></film>)");
  EXPECT_EQ(lanczos.kind, FilterKind::lanczos);
  EXPECT_EQ(lanczos.radius, 3.0);  // Mitsuba's default of 3 lobes
  lanczos = filter_of(R"(<film type="hdrfilm"><rfilter type="lanczos"><integer name="lobes" value="2"/>
      </rfilter></film>)");
  EXPECT_EQ(lanczos.radius, 2.0);
  // Without <rfilter>, and without <film>, Mitsuba's default: gaussian, stddev 0.5.
  for (const std::string& film : {std::string(R"(<film type="hdrfilm"/>)"), std::string()}) {
    PixelFilter fallback = film.empty()
                               ? with_sensor("<sensor type=\"perspective\"><float name=\"fov\" "
                                             "value=\"30\"/></sensor>")
                                     .film.filter
                               : filter_of(film);
    EXPECT_EQ(fallback.kind, FilterKind::gaussian);
    EXPECT_EQ(fallback.stddev, 0.5);
    EXPECT_EQ(fallback.radius, 2.0);
  }
}

TEST(MitsubaFilm, WhatChangesTheImageIsRefused) {
  auto film_error = [](const std::string& film) {
    return sensor_error(sensor(R"(<float name="fov" value="30"/>)", "perspective", film));
  };
  EXPECT_NE(film_error(R"(<film type="hdrfilm"><rfilter type="sinc"/></film>)")
                .find("<rfilter type=\"sinc\">: unsupported reconstruction filter (Tessera "
                      "has box, tent, gaussian, mitchell, catmullrom and lanczos)"),
            std::string::npos);
  EXPECT_NE(film_error(R"(<film type="hdrfilm"><rfilter type="lanczos"><integer name="lobes" value="0"/>
      </rfilter></film>)")
                .find("<integer name=\"lobes\">: must be a whole number from 1 to 64 (got 0)"),
            std::string::npos);
  EXPECT_NE(film_error(R"(<film type="hdrfilm"><rfilter type="mitchell"><float name="A" value="0.25"/>
      </rfilter></film>)")
                .find("\"A\""),
            std::string::npos);  // Mitsuba's docs name A and B; its code reads B and C
  EXPECT_NE(film_error(R"(<film type="hdrfilm"><rfilter type="box"><float name="radius" value="0"/>
      </rfilter></film>)")
                .find("<float name=\"radius\">: must be > 0 (got 0)"),
            std::string::npos);
  EXPECT_NE(film_error(R"(<film type="hdrfilm"><string name="pixel_format" value="luminance"/>
      <rfilter type="box"/></film>)")
                .find("\"luminance\": Tessera renders RGB"),
            std::string::npos);
  EXPECT_NE(film_error(R"(<film type="hdrfilm"><integer name="crop_width" value="10"/>
      <rfilter type="box"/></film>)")
                .find("remove the crop window"),
            std::string::npos);
  EXPECT_NE(
      film_error(R"(<film type="specfilm"><rfilter type="box"/></film>)").find("unsupported film"),
      std::string::npos);
  EXPECT_NE(film_error(R"(<film type="hdrfilm"><integer name="width" value="0"/>
      <rfilter type="box"/></film>)")
                .find("must be in [1, 32768] (got 0)"),
            std::string::npos);
}

TEST(MitsubaSampler, CountAndSeed) {
  Scene s = with_sensor(sensor(R"(<float name="fov" value="30"/>
      <sampler type="stratified"><integer name="sample_count" value="100"/>
      <integer name="seed" value="7"/><boolean name="jitter" value="false"/></sampler>)"));
  EXPECT_EQ(s.render.spp, 100);
  EXPECT_EQ(s.render.seed, 7u);
  EXPECT_EQ(with_sensor(sensor(R"(<float name="fov" value="30"/>)")).render.spp, 4);  // default
  EXPECT_NE(sensor_error(sensor(R"(<float name="fov" value="30"/><sampler type="sobol"/>)"))
                .find("unknown sampler"),
            std::string::npos);
  EXPECT_NE(sensor_error(sensor(R"(<float name="fov" value="30"/><sampler type="independent">
      <integer name="sample_count" value="0"/></sampler>)"))
                .find("must be >= 1"),
            std::string::npos);
  EXPECT_NE(sensor_error(sensor(R"(<float name="fov" value="30"/><sampler type="independent">
      <float name="sample_count" value="4"/></sampler>)"))
                .find("sample_count must be given as <integer>"),
            std::string::npos);
}

}  // namespace
}  // namespace tessera
