#include "analysis/plate_study.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "analysis/sphere_plates.hpp"
#include "common/csv.hpp"

namespace shapepress::analysis {
namespace {

Curve loading_curve(const PlateCurve& c, const std::string& label) {
  Curve curve{{0.0}, {0.0}, label};  // both plates touch at zero force
  for (std::size_t i = 0; i < c.deformation.size(); ++i)
    if (c.deformation[i] > curve.x.back()) {
      curve.x.push_back(c.deformation[i]);
      curve.y.push_back(c.top_force[i]);
    }
  return curve;
}

}  // namespace

std::optional<PlateStudy> plate_study(const std::vector<LoadedRun>& runs,
                                      std::optional<double> poisson_ratio, double from, double to) {
  std::vector<const LoadedRun*> members;
  for (const LoadedRun& run : runs)
    if (run.plate && run.plate->sub_spheres > 0) members.push_back(&run);
  // A study compares sub-sphere counts: it needs two agglomerates (N > 1), not only single
  // spheres (the demo's Hertz and multi-contact spheres are N = 1 each).
  const auto agglomerates = std::count_if(
      members.begin(), members.end(), [](const LoadedRun* r) { return r->plate->sub_spheres > 1; });
  if (agglomerates < 2) return std::nullopt;
  PlateStudy study;
  const LoadedRun* finest =
      *std::max_element(members.begin(), members.end(), [](const LoadedRun* a, const LoadedRun* b) {
        return a->plate->sub_spheres < b->plate->sub_spheres;
      });
  study.finest = finest->label;
  double reach = to;
  for (const LoadedRun* run : members)
    reach = std::min(reach, run->plate->deformation.back());
  study.from = from;
  study.to = reach;
  const Curve reference = loading_curve(*finest->plate, finest->label);
  for (const LoadedRun* run : members) {
    PlateStudyRow row;
    row.label = run->label;
    row.sub_spheres = run->plate->sub_spheres;
    row.cpu_seconds = run->plate->cpu_seconds;
    row.wall_seconds = run->plate->wall_seconds;
    const Curve curve = loading_curve(*run->plate, run->label);
    row.versus_finest = compare_curves(curve, reference, study.from, study.to);
    // The convergence test: every 1 % step of deformation in the window.
    for (int step = static_cast<int>(std::ceil(study.from * 100 - 1e-9));
         step <= static_cast<int>(std::floor(study.to * 100 + 1e-9)); ++step) {
      const double x = step / 100.0;
      const double f = interpolate(reference, x);
      if (f != 0.0)
        row.max_step_versus_finest = std::max(row.max_step_versus_finest,
                                              std::fabs(interpolate(curve, x) - f) / std::fabs(f));
    }
    if (poisson_ratio) {
      const ElasticSphere sphere = infer_sphere(*run->plate, *poisson_ratio);
      std::vector<double> approaches;
      for (double d : curve.x)
        approaches.push_back(2.0 * sphere.radius * d);
      const Curve tatara{curve.x, tatara_plate_forces(sphere, approaches), "Tatara"};
      row.versus_tatara = compare_curves(curve, tatara, study.from, study.to);
    }
    study.rows.push_back(std::move(row));
  }
  return study;
}

std::vector<Chart> plate_study_charts(const PlateStudy& study) {
  Chart cost{"CPU time against the number of sub-spheres (paper Fig. 2b)",
             "sub-spheres N",
             "CPU time to 40 % [s]",
             "sub_spheres",
             "cpu_s",
             {}};
  Series bms{"BMS, CPU seconds", {}, {}, SeriesStyle::lines, 1};
  Series wall{"BMS, wall seconds", {}, {}, SeriesStyle::dashed, 2};
  for (const PlateStudyRow& row : study.rows)
    if (row.sub_spheres > 1 && row.cpu_seconds >= 0.0) {
      bms.x.push_back(row.sub_spheres), bms.y.push_back(row.cpu_seconds);
      wall.x.push_back(row.sub_spheres), wall.y.push_back(row.wall_seconds);
    }
  const auto by_x = [](Series& s) {
    std::vector<std::size_t> order(s.x.size());
    for (std::size_t i = 0; i < order.size(); ++i)
      order[i] = i;
    std::sort(order.begin(), order.end(),
              [&](std::size_t a, std::size_t b) { return s.x[a] < s.x[b]; });
    Series sorted = s;
    for (std::size_t i = 0; i < order.size(); ++i)
      sorted.x[i] = s.x[order[i]], sorted.y[i] = s.y[order[i]];
    s = sorted;
  };
  by_x(bms), by_x(wall);
  cost.series = {bms, wall};
  Chart accuracy{fmt::format("Speed against accuracy: RMS force error over {:.0f}-{:.0f} % "
                             "deformation",
                             100 * study.from, 100 * study.to),
                 "CPU time [s]",
                 "RMS relative force error [%]",
                 "cpu_s",
                 "rms_percent",
                 {}};
  // One line per comparison through the BMS runs in order of cost (labelled by N in the CSV),
  // and the single Hertz sphere as its own points.
  Series finest{"BMS vs the finest N", {}, {}, SeriesStyle::lines, 1};
  Series tatara{"BMS vs Tatara", {}, {}, SeriesStyle::dashed, 2};
  Series hertz{"Hertz sphere vs the finest N and vs Tatara", {}, {}, SeriesStyle::points, 3};
  for (const PlateStudyRow& row : study.rows) {
    if (row.sub_spheres <= 1) {
      hertz.x.push_back(row.cpu_seconds), hertz.y.push_back(100 * row.versus_finest.rms_relative);
      if (row.versus_tatara)
        hertz.x.push_back(row.cpu_seconds),
            hertz.y.push_back(100 * row.versus_tatara->rms_relative);
      continue;
    }
    if (row.label != study.finest)
      finest.x.push_back(row.cpu_seconds), finest.y.push_back(100 * row.versus_finest.rms_relative);
    if (row.versus_tatara)
      tatara.x.push_back(row.cpu_seconds),
          tatara.y.push_back(100 * row.versus_tatara->rms_relative);
  }
  by_x(finest), by_x(tatara);
  accuracy.series = {finest, tatara};
  if (!hertz.x.empty()) accuracy.series.push_back(hertz);
  return {cost, accuracy};
}

void write_plate_study_csv(const std::filesystem::path& path, const PlateStudy& study) {
  CsvWriter csv(path, {"label", "sub_spheres", "cpu_s", "wall_s", "rms_vs_finest", "max_vs_finest",
                       "max_step_vs_finest", "rms_vs_tatara", "max_vs_tatara"});
  csv.comment(fmt::format("relative force errors over deformation [{:.4g}, {:.4g}]; finest: {}",
                          study.from, study.to, study.finest));
  csv.comment("max_step_vs_finest: largest relative difference at the 1 % deformation steps");
  for (const PlateStudyRow& r : study.rows)
    csv.row_text({r.label, fmt::format("{}", r.sub_spheres), format_number(r.cpu_seconds),
                  format_number(r.wall_seconds), format_number(r.versus_finest.rms_relative),
                  format_number(r.versus_finest.max_relative),
                  format_number(r.max_step_versus_finest),
                  r.versus_tatara ? format_number(r.versus_tatara->rms_relative) : "",
                  r.versus_tatara ? format_number(r.versus_tatara->max_relative) : ""});
  csv.commit();
}

}  // namespace shapepress::analysis
