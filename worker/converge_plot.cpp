// The convergence plot, drawn with OpenImageIO's ImageBufAlgo (render_line, render_box,
// render_text): no plotting library in C++ on Debian does log-log axes better for this one
// figure, and it keeps the tool a single binary.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <unistd.h>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include "converge.h"

namespace tessera {
namespace {

namespace IBA = OIIO::ImageBufAlgo;

constexpr float kBlack[3] = {0.1f, 0.1f, 0.1f};
constexpr float kGrid[3] = {0.86f, 0.86f, 0.86f};
constexpr float kGrey[3] = {0.55f, 0.55f, 0.55f};
constexpr float kRmseColor[3] = {0.12f, 0.47f, 0.71f};    // blue
constexpr float kRelMseColor[3] = {0.85f, 0.37f, 0.01f};  // orange
constexpr float kDenoisedColor[3] = {0.17f, 0.63f, 0.17f};  // green

/// A log-log panel: data coordinates to pixels.
struct Panel {
  int x0, y0, x1, y1;  // plot area in pixels (y0 top)
  double lx0, lx1, ly0, ly1;  // log10 range

  int px(double x) const { return x0 + int(std::lround((std::log10(x) - lx0) / (lx1 - lx0) * (x1 - x0))); }
  int py(double y) const { return y1 - int(std::lround((std::log10(y) - ly0) / (ly1 - ly0) * (y1 - y0))); }
};

class Canvas {
 public:
  Canvas(int w, int h, std::string font) : buf_(OIIO::ImageSpec(w, h, 3, OIIO::TypeDesc::FLOAT)), font_(std::move(font)) {
    const float white[3] = {1, 1, 1};
    IBA::fill(buf_, white);
  }
  void line(int xa, int ya, int xb, int yb, const float* c, int thickness = 1) {
    for (int d = -(thickness / 2); d <= thickness / 2; ++d) {
      const bool steep = std::abs(yb - ya) > std::abs(xb - xa);
      IBA::render_line(buf_, xa + (steep ? d : 0), ya + (steep ? 0 : d), xb + (steep ? d : 0),
                       yb + (steep ? 0 : d), {c, 3});
    }
  }
  void dashed(int xa, int ya, int xb, int yb, const float* c) {
    const double len = std::hypot(double(xb - xa), double(yb - ya));
    const int dashes = std::max(1, int(len / 8));
    for (int i = 0; i < dashes; i += 2) {
      const double t0 = double(i) / dashes, t1 = double(std::min(i + 1, dashes)) / dashes;
      line(int(xa + t0 * (xb - xa)), int(ya + t0 * (yb - ya)), int(xa + t1 * (xb - xa)),
           int(ya + t1 * (yb - ya)), c, 2);
    }
  }
  void marker(int x, int y, const float* c) { IBA::render_box(buf_, x - 3, y - 3, x + 3, y + 3, {c, 3}, true); }
  void text(int x, int y, const std::string& s, int size, OIIO::ImageBufAlgo::TextAlignX ax,
            OIIO::ImageBufAlgo::TextAlignY ay, const float* c = kBlack) {
    if (!text_ok_) return;
    if (!IBA::render_text(buf_, x, y, s, size, font_, {c, 3}, ax, ay)) {
      text_ok_ = false;
      std::fprintf(stderr, "converge: the plot has no labels (no font: %s)\n", buf_.geterror().c_str());
    }
  }
  void write(const std::string& path) {
    std::filesystem::path temporary = path;
    temporary += ".tmp" + std::to_string(::getpid()) + ".png";
    if (!buf_.write(temporary.string(), OIIO::TypeDesc::UINT8)) {
      std::filesystem::remove(temporary);
      throw std::runtime_error(path + ": cannot be written (" + buf_.geterror() + ")");
    }
    std::error_code error;
    std::filesystem::rename(temporary, path, error);
    if (error) {
      std::filesystem::remove(temporary, error);
      throw std::runtime_error(path + ": cannot be written");
    }
  }

 private:
  OIIO::ImageBuf buf_;
  std::string font_;
  bool text_ok_ = true;
};

std::string power_label(int e) {
  if (e >= 0 && e <= 4) return std::to_string(int(std::lround(std::pow(10.0, e))));
  return "1e" + std::to_string(e);
}

/// A series of points: x and y, paired.
struct Series {
  std::vector<double> x, y;
};

/// One log-log panel of both errors against x (spp or seconds), with the fitted RMSE line, and
/// the denoised image's RMSE (`denoised`, empty when the run did not denoise).
void draw_panel(Canvas& canvas, const Panel& p, const std::vector<double>& x,
                const std::vector<double>& rmse, const std::vector<double>& relmse,
                double rmse_slope, double relmse_slope, double fit_from, const std::string& xlabel,
                const std::string& slope_unit, const Series& denoised) {
  using AX = IBA::TextAlignX;
  using AY = IBA::TextAlignY;
  for (int e = int(std::ceil(p.lx0)); e <= int(std::floor(p.lx1)); ++e) {
    const int gx = p.px(std::pow(10.0, e));
    canvas.line(gx, p.y0, gx, p.y1, kGrid);
    canvas.text(gx, p.y1 + 6, power_label(e), 14, AX::Center, AY::Top);
  }
  for (int e = int(std::ceil(p.ly0)); e <= int(std::floor(p.ly1)); ++e) {
    const int gy = p.py(std::pow(10.0, e));
    canvas.line(p.x0, gy, p.x1, gy, kGrid);
    canvas.text(p.x0 - 6, gy, "1e" + std::to_string(e), 14, AX::Right, AY::Center);
  }
  canvas.line(p.x0, p.y0, p.x0, p.y1, kBlack);
  canvas.line(p.x0, p.y1, p.x1, p.y1, kBlack);
  canvas.line(p.x1, p.y0, p.x1, p.y1, kBlack);
  canvas.line(p.x0, p.y0, p.x1, p.y0, kBlack);
  canvas.text((p.x0 + p.x1) / 2, p.y1 + 26, xlabel, 16, AX::Center, AY::Top);

  const auto points = [&](const std::vector<double>& xs, const std::vector<double>& ys, const float* c) {
    for (size_t i = 0; i < xs.size(); ++i) {
      if (!(xs[i] > 0) || !(ys[i] > 0)) continue;
      canvas.marker(p.px(xs[i]), p.py(ys[i]), c);
      if (i > 0 && xs[i - 1] > 0 && ys[i - 1] > 0) {
        canvas.line(p.px(xs[i - 1]), p.py(ys[i - 1]), p.px(xs[i]), p.py(ys[i]), c);
      }
    }
  };
  const auto series = [&](const std::vector<double>& y, const float* c, double slope) {
    points(x, y, c);
    if (!std::isfinite(slope)) return;
    // The fitted line through the geometric mean of the fitted points.
    double sx = 0, sy = 0, xmin = std::numeric_limits<double>::infinity(), xmax = 0;
    int n = 0;
    for (size_t i = 0; i < x.size(); ++i) {
      if (x[i] < fit_from || !(y[i] > 0)) continue;
      sx += std::log10(x[i]);
      sy += std::log10(y[i]);
      xmin = std::min(xmin, x[i]);
      xmax = std::max(xmax, x[i]);
      ++n;
    }
    if (n < 2) return;
    const double mx = sx / n, my = sy / n;
    const auto yfit = [&](double xv) { return std::pow(10.0, my + slope * (std::log10(xv) - mx)); };
    canvas.dashed(p.px(xmin), p.py(yfit(xmin)), p.px(xmax), p.py(yfit(xmax)), c);
  };
  // Plain Monte Carlo's RMSE ~ x^-1/2 through the first fitted RMSE point, for comparison.
  for (size_t i = 0; i < x.size(); ++i) {
    if (x[i] < fit_from || !(rmse[i] > 0)) continue;
    const double xe = x.back();
    canvas.dashed(p.px(x[i]), p.py(rmse[i]), p.px(xe), p.py(rmse[i] * std::sqrt(x[i] / xe)), kGrey);
    break;
  }
  series(rmse, kRmseColor, rmse_slope);
  series(relmse, kRelMseColor, relmse_slope);
  points(denoised.x, denoised.y, kDenoisedColor);

  char label[96];
  std::snprintf(label, sizeof label, "RMSE, fitted slope %.3f %s", rmse_slope, slope_unit.c_str());
  canvas.marker(p.x1 - 300, p.y0 + 18, kRmseColor);
  canvas.text(p.x1 - 290, p.y0 + 18, label, 14, AX::Left, AY::Center);
  std::snprintf(label, sizeof label, "relative MSE, fitted slope %.3f", relmse_slope);
  canvas.marker(p.x1 - 300, p.y0 + 40, kRelMseColor);
  canvas.text(p.x1 - 290, p.y0 + 40, label, 14, AX::Left, AY::Center);
  canvas.line(p.x1 - 306, p.y0 + 62, p.x1 - 294, p.y0 + 62, kGrey, 2);
  canvas.text(p.x1 - 290, p.y0 + 62, "slope -0.5 (plain Monte Carlo)", 14, AX::Left, AY::Center);
  if (!denoised.x.empty()) {
    canvas.marker(p.x1 - 300, p.y0 + 84, kDenoisedColor);
    canvas.text(p.x1 - 290, p.y0 + 84, "RMSE denoised (guides and denoising timed)", 14, AX::Left, AY::Center);
  }
  canvas.text(p.x0, p.y0 - 6, "error", 14, AX::Left, AY::Bottom);
}

}  // namespace

void write_convergence_plot(const ConvergenceResult& result, const std::string& path, int width,
                            int height, const std::string& font) {
  std::vector<double> spp, seconds, rmse, relmse;
  Series denoised_by_spp, denoised_by_time;
  for (const ConvergenceRow& r : result.rows) {
    spp.push_back(r.spp);
    seconds.push_back(r.seconds);
    rmse.push_back(r.rmse);
    relmse.push_back(r.relmse);
    if (r.denoised) {
      denoised_by_spp.x.push_back(r.spp);
      denoised_by_spp.y.push_back(r.denoised->rmse);
      denoised_by_time.x.push_back(r.denoised->seconds);
      denoised_by_time.y.push_back(r.denoised->rmse);
    }
  }
  // Shared y range over both errors, whole decades.
  double ymin = std::numeric_limits<double>::infinity(), ymax = 0;
  for (const std::vector<double>* v : {&rmse, &relmse, &denoised_by_spp.y}) {
    for (double y : *v) {
      if (y > 0) {
        ymin = std::min(ymin, y);
        ymax = std::max(ymax, y);
      }
    }
  }
  if (!(ymax > 0)) ymin = 1e-3, ymax = 1;
  const auto decades = [](double lo, double hi, double* l0, double* l1) {
    *l0 = std::floor(std::log10(lo));
    *l1 = std::ceil(std::log10(hi));
    if (*l1 <= *l0) *l1 = *l0 + 1;
  };
  double ly0, ly1, sx0, sx1, tx0, tx1;
  decades(ymin, ymax, &ly0, &ly1);
  decades(spp.empty() ? 1.0 : spp.front(), spp.empty() ? 10.0 : spp.back(), &sx0, &sx1);
  const double last_second = std::max(seconds.empty() ? 1.0 : seconds.back(),
                                      denoised_by_time.x.empty() ? 0.0 : denoised_by_time.x.back());
  decades(seconds.empty() ? 0.1 : std::max(1e-6, seconds.front()), std::max(1e-6, last_second), &tx0, &tx1);

  Canvas canvas(width, height, font.empty() ? "DejaVuSans" : font);
  const int margin_l = 70, margin_r = 20, top = 50, bottom = height - 60, gap = 80;
  const int panel_w = (width - margin_l - margin_r - gap) / 2;
  const Panel by_spp{margin_l, top, margin_l + panel_w, bottom, sx0, sx1, ly0, ly1};
  const Panel by_time{margin_l + panel_w + gap, top, margin_l + 2 * panel_w + gap, bottom, tx0, tx1, ly0, ly1};

  char title[256];
  std::snprintf(title, sizeof title, "%s, %dx%d, max_depth %d: error against the reference",
                result.scene_name.c_str(), result.options.width, result.options.height,
                result.options.max_depth);
  canvas.text(width / 2, 14, title, 18, IBA::TextAlignX::Center, IBA::TextAlignY::Top);
  draw_panel(canvas, by_spp, spp, rmse, relmse, result.fit.rmse_vs_spp, result.fit.relmse_vs_spp,
             result.fit.spp_from, "samples per pixel", "", denoised_by_spp);
  double t_from = std::numeric_limits<double>::infinity();
  for (const ConvergenceRow& r : result.rows) {
    if (r.spp >= result.fit.spp_from) t_from = std::min(t_from, r.seconds);
  }
  draw_panel(canvas, by_time, seconds, rmse, relmse, result.fit.rmse_vs_seconds,
             result.fit.relmse_vs_seconds, t_from, "wall time (s)", "", denoised_by_time);
  canvas.write(path);
}

}  // namespace tessera
