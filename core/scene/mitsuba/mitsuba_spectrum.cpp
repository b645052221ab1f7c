#include "scene/mitsuba/mitsuba_spectrum.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "scene/mitsuba/mitsuba_values.h"

namespace tessera {
namespace {

constexpr double kCieMin = 360, kCieMax = 830;
constexpr int kCieSamples = 95;
/// Scales the CIE curves so that a unit spectrum has luminance 1 (Mitsuba's
/// MI_CIE_Y_NORMALIZATION).
constexpr double kCieYNormalization = 1.0 / 106.7502593994140625;
/// Scales D65 to 1 at 560 nm (MI_CIE_D65_NORMALIZATION).
constexpr double kD65Normalization = 1.0 / 98.99741751876255;

/// The CIE 1931 2-degree colour matching functions x, y, z and the CIE D65 illuminant's
/// relative power, every 5 nm from 360 to 830 nm (CIE 015:2018 tables, the same Mitsuba 3
/// tabulates in include/mitsuba/core/spectrum.h and src/core/spectrum.cpp). No Debian library
/// ships them for C++; they are standard data, so they are written out here.
constexpr std::array<std::array<double, 4>, kCieSamples> kCie = {{
    {0.0001299, 3.917e-06, 0.0006061, 46.6383},  // 360 nm
    {0.0002321, 6.965e-06, 0.001086, 49.3637},  // 365 nm
    {0.0004149, 1.239e-05, 0.001946, 52.0891},  // 370 nm
    {0.0007416, 2.202e-05, 0.003486, 51.0323},  // 375 nm
    {0.001368, 3.9e-05, 0.006450001, 49.9755},  // 380 nm
    {0.002236, 6.4e-05, 0.01054999, 52.3118},  // 385 nm
    {0.004243, 0.00012, 0.02005001, 54.6482},  // 390 nm
    {0.00765, 0.000217, 0.03621, 68.7015},  // 395 nm
    {0.01431, 0.000396, 0.06785001, 82.7549},  // 400 nm
    {0.02319, 0.00064, 0.1102, 87.1204},  // 405 nm
    {0.04351, 0.00121, 0.2074, 91.486},  // 410 nm
    {0.07763, 0.00218, 0.3713, 92.4589},  // 415 nm
    {0.13438, 0.004, 0.6456, 93.4318},  // 420 nm
    {0.21477, 0.0073, 1.03905, 90.057},  // 425 nm
    {0.2839, 0.0116, 1.3856, 86.6823},  // 430 nm
    {0.3285, 0.01684, 1.62296, 95.7736},  // 435 nm
    {0.34828, 0.023, 1.74706, 104.865},  // 440 nm
    {0.34806, 0.0298, 1.7826, 110.936},  // 445 nm
    {0.3362, 0.038, 1.77211, 117.008},  // 450 nm
    {0.3187, 0.048, 1.7441, 117.41},  // 455 nm
    {0.2908, 0.06, 1.6692, 117.812},  // 460 nm
    {0.2511, 0.0739, 1.5281, 116.336},  // 465 nm
    {0.19536, 0.09098, 1.28764, 114.861},  // 470 nm
    {0.1421, 0.1126, 1.0419, 115.392},  // 475 nm
    {0.09564, 0.13902, 0.8129501, 115.923},  // 480 nm
    {0.05795001, 0.1693, 0.6162, 112.367},  // 485 nm
    {0.03201, 0.20802, 0.46518, 108.811},  // 490 nm
    {0.0147, 0.2586, 0.3533, 109.082},  // 495 nm
    {0.0049, 0.323, 0.272, 109.354},  // 500 nm
    {0.0024, 0.4073, 0.2123, 108.578},  // 505 nm
    {0.0093, 0.503, 0.1582, 107.802},  // 510 nm
    {0.0291, 0.6082, 0.1117, 106.296},  // 515 nm
    {0.06327, 0.71, 0.07824999, 104.79},  // 520 nm
    {0.1096, 0.7932, 0.05725001, 106.239},  // 525 nm
    {0.1655, 0.862, 0.04216, 107.689},  // 530 nm
    {0.2257499, 0.9148501, 0.02984, 106.047},  // 535 nm
    {0.2904, 0.954, 0.0203, 104.405},  // 540 nm
    {0.3597, 0.9803, 0.0134, 104.225},  // 545 nm
    {0.4334499, 0.9949501, 0.008749999, 104.046},  // 550 nm
    {0.5120501, 1, 0.005749999, 102.023},  // 555 nm
    {0.5945, 0.995, 0.0039, 100},  // 560 nm
    {0.6784, 0.9786, 0.002749999, 98.1671},  // 565 nm
    {0.7621, 0.952, 0.0021, 96.3342},  // 570 nm
    {0.8425, 0.9154, 0.0018, 96.0611},  // 575 nm
    {0.9163, 0.87, 0.001650001, 95.788},  // 580 nm
    {0.9786, 0.8163, 0.0014, 92.2368},  // 585 nm
    {1.0263, 0.757, 0.0011, 88.6856},  // 590 nm
    {1.0567, 0.6949, 0.001, 89.3459},  // 595 nm
    {1.0622, 0.631, 0.0008, 90.0062},  // 600 nm
    {1.0456, 0.5668, 0.0006, 89.8026},  // 605 nm
    {1.0026, 0.503, 0.00034, 89.5991},  // 610 nm
    {0.9384, 0.4412, 0.00024, 88.6489},  // 615 nm
    {0.8544499, 0.381, 0.00019, 87.6987},  // 620 nm
    {0.7514, 0.321, 0.0001, 85.4936},  // 625 nm
    {0.6424, 0.265, 4.999999e-05, 83.2886},  // 630 nm
    {0.5419, 0.217, 3e-05, 83.4939},  // 635 nm
    {0.4479, 0.175, 2e-05, 83.6992},  // 640 nm
    {0.3608, 0.1382, 1e-05, 81.863},  // 645 nm
    {0.2835, 0.107, 0, 80.0268},  // 650 nm
    {0.2187, 0.0816, 0, 80.1207},  // 655 nm
    {0.1649, 0.061, 0, 80.2146},  // 660 nm
    {0.1212, 0.04458, 0, 81.2462},  // 665 nm
    {0.0874, 0.032, 0, 82.2778},  // 670 nm
    {0.0636, 0.0232, 0, 80.281},  // 675 nm
    {0.04677, 0.017, 0, 78.2842},  // 680 nm
    {0.0329, 0.01192, 0, 74.0027},  // 685 nm
    {0.0227, 0.00821, 0, 69.7213},  // 690 nm
    {0.01584, 0.005723, 0, 70.6652},  // 695 nm
    {0.01135916, 0.004102, 0, 71.6091},  // 700 nm
    {0.008110916, 0.002929, 0, 72.979},  // 705 nm
    {0.005790346, 0.002091, 0, 74.349},  // 710 nm
    {0.004109457, 0.001484, 0, 67.9765},  // 715 nm
    {0.002899327, 0.001047, 0, 61.604},  // 720 nm
    {0.00204919, 0.00074, 0, 65.7448},  // 725 nm
    {0.001439971, 0.00052, 0, 69.8856},  // 730 nm
    {0.0009999493, 0.0003611, 0, 72.4863},  // 735 nm
    {0.0006900786, 0.0002492, 0, 75.087},  // 740 nm
    {0.0004760213, 0.0001719, 0, 69.3398},  // 745 nm
    {0.0003323011, 0.00012, 0, 63.5927},  // 750 nm
    {0.0002348261, 8.48e-05, 0, 55.0054},  // 755 nm
    {0.0001661505, 6e-05, 0, 46.4182},  // 760 nm
    {0.000117413, 4.24e-05, 0, 56.6118},  // 765 nm
    {8.307527e-05, 3e-05, 0, 66.8054},  // 770 nm
    {5.870652e-05, 2.12e-05, 0, 65.0941},  // 775 nm
    {4.150994e-05, 1.499e-05, 0, 63.3828},  // 780 nm
    {2.935326e-05, 1.06e-05, 0, 63.8434},  // 785 nm
    {2.067383e-05, 7.4657e-06, 0, 64.304},  // 790 nm
    {1.455977e-05, 5.2578e-06, 0, 61.8779},  // 795 nm
    {1.025398e-05, 3.7029e-06, 0, 59.4519},  // 800 nm
    {7.221456e-06, 2.6078e-06, 0, 55.7054},  // 805 nm
    {5.085868e-06, 1.8366e-06, 0, 51.959},  // 810 nm
    {3.581652e-06, 1.2934e-06, 0, 54.6998},  // 815 nm
    {2.522525e-06, 9.1093e-07, 0, 57.4406},  // 820 nm
    {1.776509e-06, 6.4153e-07, 0, 58.8765},  // 825 nm
    {1.251141e-06, 4.5181e-07, 0, 60.3125},  // 830 nm
}};

/// Linear interpolation in the 5 nm tables, as Mitsuba's cie1931_xyz and cie_d65 (zero outside).
std::array<double, 4> cie_at(double wavelength) {
  if (!(wavelength >= kCieMin && wavelength <= kCieMax)) return {0, 0, 0, 0};
  double t = (wavelength - kCieMin) * ((kCieSamples - 1) / (kCieMax - kCieMin));
  int i = std::min(int(t), kCieSamples - 2);
  double w1 = t - i, w0 = 1 - w1;
  std::array<double, 4> out;
  for (int c = 0; c < 4; ++c) out[c] = w0 * kCie[i][c] + w1 * kCie[i + 1][c];
  out[3] *= kD65Normalization;
  return out;
}

/// XYZ to linear sRGB (Mitsuba's xyz_to_srgb).
glm::dvec3 xyz_to_srgb(const glm::dvec3& xyz) {
  return {3.240479 * xyz.x - 1.537150 * xyz.y - 0.498535 * xyz.z,
          -0.969256 * xyz.x + 1.875991 * xyz.y + 0.041556 * xyz.z,
          0.055648 * xyz.x - 0.204043 * xyz.y + 1.057311 * xyz.z};
}

std::optional<glm::dvec3> list_to_rgb(const std::vector<double>& wavelengths,
                                      const std::vector<double>& values, MitsubaColorRole role) {
  const bool d65 = role != MitsubaColorRole::emission;
  glm::dvec3 xyz(0);
  constexpr int kSteps = 1000;
  for (int i = 0; i < kSteps; ++i) {
    double w = kCieMin + (i / double(kSteps - 1)) * (kCieMax - kCieMin);
    if (w < wavelengths.front() || w > wavelengths.back()) continue;
    size_t index = size_t(std::upper_bound(wavelengths.begin(), wavelengths.end(), w) -
                          wavelengths.begin());
    index = std::clamp<size_t>(index, 1, wavelengths.size() - 1) - 1;
    double w0 = wavelengths[index], w1 = wavelengths[index + 1];
    double v = ((w - w1) * values[index] + (w0 - w) * values[index + 1]) / (w0 - w1);
    std::array<double, 4> cie = cie_at(w);
    glm::dvec3 matching(cie[0], cie[1], cie[2]);
    xyz += matching * v * (d65 ? cie[3] : 1.0);
  }
  xyz *= (kCieMax - kCieMin) * kCieYNormalization / kSteps;
  glm::dvec3 rgb = xyz_to_srgb(xyz);
  for (int c = 0; c < 3; ++c) {
    rgb[c] = role == MitsubaColorRole::reflectance ? std::clamp(rgb[c], 0.0, 1.0)
                                                   : std::max(rgb[c], 0.0);
  }
  return rgb;
}

}  // namespace

std::optional<glm::dvec3> mitsuba_spectrum_to_rgb(std::string_view value, MitsubaColorRole role,
                                                  std::string& error) {
  if (std::optional<double> uniform = parse_mitsuba_float(value)) {
    if (role == MitsubaColorRole::emission) return *uniform * xyz_to_srgb(glm::dvec3(1));
    return glm::dvec3(*uniform);
  }
  std::vector<double> wavelengths, values;
  for (std::string_view pair : split_mitsuba_list(value)) {
    size_t colon = pair.find(':');
    std::optional<double> w, v;
    if (colon != std::string_view::npos) {
      w = parse_mitsuba_float(pair.substr(0, colon));
      v = parse_mitsuba_float(pair.substr(colon + 1));
    }
    if (!w || !v) {
      error = "\"" + std::string(pair) +
              "\" is not a wavelength:value pair (write value=\"0.5\" or \"400:0.1, 700:0.9\")";
      return std::nullopt;
    }
    if (!wavelengths.empty() && !(*w > wavelengths.back())) {
      error = "wavelengths must increase (" + std::string(pair) + ")";
      return std::nullopt;
    }
    wavelengths.push_back(*w);
    values.push_back(*v);
  }
  if (wavelengths.size() < 2) {
    error = "a spectrum is one value or at least two wavelength:value pairs";
    return std::nullopt;
  }
  return list_to_rgb(wavelengths, values, role);
}

}  // namespace tessera
