#include "icanc/core/evaluation/segment_energy.hpp"

#include <algorithm>
#include <numeric>
#include <stdexcept>

namespace icanc {

std::vector<EnergyRow> segmentedEnergyTable(const LampCatalogue& catalogue,
                                            const std::vector<DriveCase>& cases, Beam beam,
                                            std::size_t segments, std::size_t lit_per_object) {
  if (segments == 0 || lit_per_object == 0)
    throw std::invalid_argument("a segmented lamp needs >= 1 segment and >= 1 lit per object");
  const double lit_fraction = double(std::min(lit_per_object, segments)) / double(segments);
  std::vector<EnergyRow> rows = energyTable(catalogue, cases, beam);
  for (EnergyRow& r : rows) {
    if (r.case_name == cases.front().name) continue;  // the worst case: every segment always on
    const double baseline = r.wh + r.saving_wh;
    r.wh *= lit_fraction;
    r.saving_wh = baseline - r.wh;
    r.saving_pct = baseline > 0.0 ? 100.0 * r.saving_wh / baseline : 0.0;
  }
  return rows;
}

SegmentEnergy integrateSegmentEnergy(const std::vector<LevelSample>& samples, double end_s,
                                     const std::vector<double>& segment_watts) {
  if (segment_watts.empty()) throw std::invalid_argument("a segmented lamp needs >= 1 segment");
  SegmentEnergy out;
  if (samples.empty()) return out;
  std::vector<double> times(samples.size());
  std::transform(samples.begin(), samples.end(), times.begin(), [](const LevelSample& s) { return s.t_s; });
  checkSampleTimes(times, end_s);
  const double end = std::max(end_s, samples.back().t_s);
  const double all_w = std::accumulate(segment_watts.begin(), segment_watts.end(), 0.0);
  double joules = 0.0;
  for (std::size_t k = 0; k < samples.size(); ++k) {
    const std::vector<float>& levels = samples[k].levels;
    const double dt = (k + 1 < samples.size() ? samples[k + 1].t_s : end) - samples[k].t_s;
    double w = all_w;  // a fault command (other level count): every segment on
    if (levels.size() == segment_watts.size())
      w = std::inner_product(levels.begin(), levels.end(), segment_watts.begin(), 0.0,
                             std::plus<double>(), [](float l, double sw) { return std::clamp(double(l), 0.0, 1.0) * sw; });
    joules += w * dt;
    const bool any = levels.size() != segment_watts.size() ||
                     std::any_of(levels.begin(), levels.end(), [](float l) { return l > 0.0f; });
    out.any_on_s += any ? dt : 0.0;
  }
  out.span_s = end - samples.front().t_s;
  out.wh = joules / 3600.0;
  out.wh_all_on = wattHours(all_w, out.span_s / 3600.0);
  return out;
}

}  // namespace icanc
