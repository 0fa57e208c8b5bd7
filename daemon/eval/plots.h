// `saccade eval`'s plots: a gnuplot script over the run's CSV files (thresholds.csv, sweep.csv),
// left beside them to restyle by hand, and the PNGs it draws. Every plot has a title, axis
// labels with units, its legend below the data, and at most kMaxSeries series: configurations
// are ranked (true positives at the 8 cm rule, then fewest false positives) and split into
// pages of that many, the best first.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace saccade::eval {

/// Series a plot holds at most (gnuplot's default colours repeat after 8).
inline constexpr std::size_t kMaxSeries = 8;

/// A configuration as table.csv gives it: its name and its counts at the 8 cm rule.
struct PlotSeries {
  std::string name;
  int tp = 0, fp = 0;
};

/// The script and the PNGs it writes (file names, in the order drawn).
struct PlotScript {
  std::string text;
  std::vector<std::string> pngs;
};

/// The gnuplot script for `configs` (in table order; ranked here) over `scenes` frames or
/// cases, and the swept configurations' plots when `swept` names any.
PlotScript MakePlotScript(const std::vector<PlotSeries>& configs,
                          const std::vector<std::string>& swept, int scenes);

/// Reads `dir`/table.csv (configurations, their counts and the number of scenes) and
/// `dir`/sweep.csv (which were swept), writes `dir`/plot.gp and runs gnuplot on it in `dir`
/// (its messages in plot.log). False with `error` when a file is missing or malformed or
/// gnuplot fails; `pngs` names what was drawn.
bool WritePlots(const std::filesystem::path& dir, std::vector<std::string>* pngs,
                std::string* error);

}  // namespace saccade::eval
