#include "denoise/oidn_library.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <string>
#include <vector>

#include "denoise/denoised_outputs.h"

namespace tessera {
namespace {

TEST(OidnLibraryCandidates, ConfiguredPathThenTheSystemsSearch) {
  EXPECT_EQ(oidn_library_candidates("", "/prefix/lib/libOpenImageDenoise.so.2"),
            (std::vector<std::string>{"/prefix/lib/libOpenImageDenoise.so.2", kOidnSoname}));
  EXPECT_EQ(oidn_library_candidates("", ""), (std::vector<std::string>{kOidnSoname}));
}

TEST(OidnLibraryCandidates, ANamedLibraryIsTheOnlyCandidate) {
  EXPECT_EQ(oidn_library_candidates("/mine/libOpenImageDenoise.so.2", "/prefix/lib/x.so.2"),
            (std::vector<std::string>{"/mine/libOpenImageDenoise.so.2"}));
}

TEST(OidnLibraryCandidates, TheFlagComesBeforeTheEnvironment) {
  ASSERT_EQ(setenv("TESSERA_OIDN_LIBRARY", "/from/env.so", 1), 0);
  EXPECT_EQ(named_oidn_library("/from/flag.so"), "/from/flag.so");
  EXPECT_EQ(named_oidn_library(""), "/from/env.so");
  ASSERT_EQ(unsetenv("TESSERA_OIDN_LIBRARY"), 0);
  EXPECT_EQ(named_oidn_library(""), "");
}

TEST(OidnLibraryLoad, AMissingLibraryIsRefusedInOneLineSayingHowToInstallIt) {
  try {
    OidnLibrary::load({"/nonexistent/libOpenImageDenoise.so.2"});
    FAIL() << "loaded a missing library";
  } catch (const DenoiserUnavailable& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("/nonexistent/libOpenImageDenoise.so.2"), std::string::npos) << what;
    EXPECT_NE(what.find("scripts/install-deps.sh"), std::string::npos) << what;
    EXPECT_NE(what.find("--oidn-library"), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
}

TEST(OidnLibraryLoad, ALibraryWithoutOidnsFunctionsIsRefused) {
  try {
    OidnLibrary::load({"libm.so.6"});
    FAIL() << "took libm for Open Image Denoise";
  } catch (const DenoiserUnavailable& e) {
    EXPECT_NE(std::string(e.what()).find("libm.so.6: no oidnNewDevice"), std::string::npos)
        << e.what();
  }
}

TEST(DenoisedOutputPaths, BesideEachOutputWithAnExrForAPng) {
  EXPECT_EQ(denoised_output_paths({"out/a.exr"}), (std::vector<std::string>{"out/a.denoised.exr"}));
  EXPECT_EQ(denoised_output_paths({"a.PNG"}),
            (std::vector<std::string>{"a.denoised.PNG", "a.denoised.exr"}));
  EXPECT_EQ(denoised_output_paths({"a.exr", "a.png"}),
            (std::vector<std::string>{"a.denoised.exr", "a.denoised.png"}));
  EXPECT_EQ(denoised_output_paths({"v1.2/a.b.exr"}),
            (std::vector<std::string>{"v1.2/a.b.denoised.exr"}));
}

}  // namespace
}  // namespace tessera
