#include "imaging/outputs.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "common/atomic_file.hpp"
#include "common/csv.hpp"
#include "common/error.hpp"

namespace shapepress::imaging {
namespace {

void write_mat(const std::filesystem::path& path, const cv::Mat& image) {
  std::vector<std::uint8_t> bytes;
  std::string ext = path.extension().string();
  if (!cv::imencode(ext.empty() ? ".png" : ext, image, bytes))
    throw InputError(fmt::format("{}: cannot encode an image with this extension", path.string()));
  write_file_atomically(
      path, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

cv::Mat to_bgr(const GrayImage& image) {
  cv::Mat gray(image.height, image.width, CV_32F, const_cast<float*>(image.pixels.data())), g8, bgr;
  gray.convertTo(g8, CV_8U, 255.0);
  cv::cvtColor(g8, bgr, cv::COLOR_GRAY2BGR);
  return bgr;
}

// A minimal chart: axes with a few labelled ticks, then bars or a polyline in data units.
class Chart {
 public:
  Chart(std::string title, std::string x_label, double x0, double x1, double y0, double y1,
        bool log_x = false)
      : canvas_(420, 640, CV_8UC3, cv::Scalar(255, 255, 255)),
        log_x_(log_x),
        x0_(tx(x0)),
        x1_(tx(x1)),
        y0_(y0),
        y1_(y1 > y0 ? y1 : y0 + 1) {
    cv::putText(canvas_, title, {70, 28}, cv::FONT_HERSHEY_SIMPLEX, 0.6, {0, 0, 0}, 1, cv::LINE_AA);
    cv::putText(canvas_, x_label, {260, 410}, cv::FONT_HERSHEY_SIMPLEX, 0.45, {0, 0, 0}, 1,
                cv::LINE_AA);
    cv::rectangle(canvas_, cv::Point(left, top), cv::Point(right, bottom), {0, 0, 0});
    for (int k = 0; k <= 4; ++k) {
      double fx = x0_ + (x1_ - x0_) * k / 4, fy = y0_ + (y1_ - y0_) * k / 4;
      int px = left + (right - left) * k / 4, py = bottom - (bottom - top) * k / 4;
      cv::putText(canvas_, fmt::format("{:.3g}", log_x_ ? std::pow(10.0, fx) : fx),
                  {px - 18, bottom + 18}, cv::FONT_HERSHEY_SIMPLEX, 0.4, {0, 0, 0}, 1, cv::LINE_AA);
      cv::putText(canvas_, fmt::format("{:.3g}", fy), {8, py + 4}, cv::FONT_HERSHEY_SIMPLEX, 0.4,
                  {0, 0, 0}, 1, cv::LINE_AA);
    }
  }
  void bars(const std::vector<double>& edges, const std::vector<double>& heights,
            cv::Scalar colour) {
    for (std::size_t i = 0; i + 1 < edges.size() && i < heights.size(); ++i)
      cv::rectangle(canvas_, point(edges[i], heights[i]), point(edges[i + 1], y0_), colour,
                    cv::FILLED);
  }
  void line(const std::vector<double>& x, const std::vector<double>& y, cv::Scalar colour,
            const std::string& legend, int legend_row) {
    std::vector<cv::Point> points;
    for (std::size_t i = 0; i < x.size(); ++i)
      points.push_back(point(x[i], y[i]));
    cv::polylines(canvas_, points, false, colour, 2, cv::LINE_AA);
    cv::putText(canvas_, legend, {right - 150, top + 20 + 18 * legend_row},
                cv::FONT_HERSHEY_SIMPLEX, 0.45, colour, 1, cv::LINE_AA);
  }
  void save(const std::filesystem::path& path) const { write_mat(path, canvas_); }

 private:
  static constexpr int left = 60, right = 620, top = 40, bottom = 380;
  double tx(double x) const { return log_x_ ? std::log10(x) : x; }
  cv::Point point(double x, double y) const {
    double u = (tx(x) - x0_) / (x1_ - x0_), v = (std::clamp(y, y0_, y1_) - y0_) / (y1_ - y0_);
    return {left + static_cast<int>(u * (right - left)),
            bottom - static_cast<int>(v * (bottom - top))};
  }
  cv::Mat canvas_;
  bool log_x_;
  double x0_, x1_, y0_, y1_;
};

}  // namespace

void write_particles_csv(const std::filesystem::path& path,
                         const std::vector<ImageResult>& images) {
  std::vector<std::string> columns = {"image",
                                      "particle",
                                      "centroid_x_px",
                                      "centroid_y_px",
                                      "centroid_x_m",
                                      "centroid_y_m",
                                      "area_px",
                                      "area_m2",
                                      "outline_area_m2",
                                      "perimeter_m",
                                      "equivalent_diameter_px",
                                      "equivalent_diameter_m",
                                      "feret_max_m",
                                      "feret_min_m",
                                      "feret_max_angle_deg",
                                      "feret_min_angle_deg",
                                      "aspect_ratio",
                                      "feret_ratio_imagej",
                                      "circularity",
                                      "solidity",
                                      "convexity",
                                      "ellipse_major_m",
                                      "ellipse_minor_m",
                                      "ellipse_angle_deg",
                                      "fourier_r0_m"};
  for (int n = 0; n <= fourier_max_order; ++n)
    columns.push_back(fmt::format("D{}", n));
  CsvWriter csv(path, columns);
  csv.comment(
      "shapepress shape-stats: one row per particle; ImageJ definitions (area = pixel "
      "count, traced perimeter, Feret = calipers of the convex hull); D0..D32 Fourier "
      "descriptors of r(theta), Mollon & Zhao 2012 normalisation (D0 = 1)");
  for (const ImageResult& image : images) {
    const double px = image.report.pixel_size_m;
    std::string name = std::filesystem::path(image.report.file).filename().string();
    for (const ParticleMeasurement& m : image.particles) {
      std::vector<double> v = {m.centroid.x,
                               m.centroid.y,
                               m.centroid.x * px,
                               m.centroid.y * px,
                               m.area,
                               m.area * px * px,
                               m.outline_area * px * px,
                               m.perimeter * px,
                               m.equivalent_diameter,
                               m.equivalent_diameter * px,
                               m.feret.max * px,
                               m.feret.min * px,
                               m.feret.max_angle,
                               m.feret.min_angle,
                               m.aspect_ratio,
                               m.feret_imagej_ratio,
                               m.circularity,
                               m.solidity,
                               m.convexity,
                               m.ellipse_major * px,
                               m.ellipse_minor * px,
                               m.ellipse_angle,
                               m.fourier_mean_radius * px};
      v.insert(v.end(), m.fourier.begin(), m.fourier.end());
      std::vector<std::string> cells = {name, std::to_string(m.label)};
      for (double x : v)
        cells.push_back(format_number(x));
      csv.row_text(cells);
    }
  }
  csv.commit();
}

void write_overlay_png(const std::filesystem::path& path, const ImageResult& image) {
  cv::Mat canvas = to_bgr(image.image);
  for (const ParticleMeasurement& m : image.particles) {
    std::vector<cv::Point> outline;
    for (const Point2& p : m.outline)
      outline.emplace_back(static_cast<int>(p.x), static_cast<int>(p.y));
    cv::polylines(canvas, outline, true, cv::Scalar(40, 220, 40), 1);
    cv::putText(canvas, std::to_string(m.label),
                cv::Point(static_cast<int>(m.centroid.x) - 6, static_cast<int>(m.centroid.y) + 4),
                cv::FONT_HERSHEY_SIMPLEX, 0.4, cv::Scalar(30, 30, 230), 1, cv::LINE_AA);
  }
  write_mat(path, canvas);
}

void write_plots(const std::filesystem::path& folder, const ShapeSummary& s) {
  std::vector<double> edges_um;
  for (double e : s.size.edges_m)
    edges_um.push_back(e * 1e6);
  Chart size("Size distribution (equivalent circle diameter)", "x [um]", edges_um.front(),
             edges_um.back(), 0.0, 1.0, true);
  size.line(edges_um, s.size.Q0, {200, 80, 0}, "Q0 (number)", 0);
  size.line(edges_um, s.size.Q3, {0, 0, 200}, "Q3 (volume)", 1);
  size.save(folder / "size_distribution.png");

  std::vector<double> counts(s.asr.counts.begin(), s.asr.counts.end());
  Chart asr(fmt::format("Aspect ratio (Feret min/max), S50 = {:.3f}", s.asr.s50), "ASR", 0.0, 1.0,
            0.0, *std::max_element(counts.begin(), counts.end()) * 1.1);
  asr.bars(s.asr.edges, counts, {180, 120, 60});
  asr.save(folder / "asr_histogram.png");

  std::vector<double> n, d;
  for (int k = 1; k <= fourier_max_order; ++k) {
    n.push_back(k);
    d.push_back(s.fourier.mean_spectrum[k]);
  }
  Chart spectrum(fmt::format("Mean Fourier spectrum: D2 {:.3f} D3 {:.3f} D8 {:.4f}", s.fourier.D2,
                             s.fourier.D3, s.fourier.D8),
                 "harmonic n", 1.0, fourier_max_order, 0.0,
                 std::max(1e-6, *std::max_element(d.begin(), d.end()) * 1.1));
  spectrum.line(n, d, {0, 0, 200}, "mean Dn", 0);
  spectrum.save(folder / "fourier_spectrum.png");
}

void write_gray_image(const std::filesystem::path& path, const GrayImage& image) {
  cv::Mat gray(image.height, image.width, CV_32F, const_cast<float*>(image.pixels.data())), g8;
  gray.convertTo(g8, CV_8U, 255.0);
  write_mat(path, g8);
}

void write_truth_csv(const std::filesystem::path& path, const SynthScene& scene,
                     double pixel_size_m) {
  CsvWriter csv(path, {"particle", "kind", "partner", "centroid_x_px", "centroid_y_px",
                       "rotation_deg", "area_px", "equivalent_diameter_px", "equivalent_diameter_m",
                       "feret_max_px", "feret_min_px", "aspect_ratio", "D2"});
  csv.comment(
      "shapepress synth-images ground truth: exact outlines before blur and noise; "
      "partner = id of the touching particle (0: none)");
  for (const SynthParticle& p : scene.particles) {
    csv.row_text(
        {std::to_string(p.id), p.kind, std::to_string(p.partner), format_number(p.centre.x),
         format_number(p.centre.y), format_number(p.rotation_deg), format_number(p.area_px),
         format_number(p.equivalent_diameter_px),
         format_number(p.equivalent_diameter_px * pixel_size_m), format_number(p.feret_max_px),
         format_number(p.feret_min_px), format_number(p.aspect_ratio), format_number(p.D2)});
  }
  csv.commit();
}

}  // namespace shapepress::imaging
