#include "daemon/eval/plots.h"

#include "io/formats/output_file.h"

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>
#include <system_error>

namespace saccade::eval {
namespace {

namespace fs = std::filesystem;

// A gnuplot double-quoted string (its escapes are processed, so \ and " are escaped).
std::string Quoted(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

// "NAME.png" for page 1, "NAME-K.png" for page K.
std::string PageFile(const std::string& stem, std::size_t page) {
  return stem + (page == 0 ? "" : "-" + std::to_string(page + 1)) + ".png";
}

// One plot per page of at most kMaxSeries names: each series is column `y` of `csv` against
// its column 2 (metres, drawn in cm) where column 1 is the series' name (and `keep` holds).
struct Figure {
  std::string stem, title, ylabel, csv, y, keep;
};

void AddPages(const Figure& f, const std::vector<std::string>& names, const std::string& ranked_by,
              std::ostringstream& gp, std::vector<std::string>* pngs) {
  const std::size_t pages = (names.size() + kMaxSeries - 1) / kMaxSeries;
  for (std::size_t page = 0; page < pages; ++page) {
    const std::size_t first = page * kMaxSeries;
    const std::size_t last = std::min(names.size(), first + kMaxSeries);
    std::string title = f.title;
    if (pages > 1) {
      // Which configurations this page holds, and where the others are.
      title += "\\nconfigurations " + std::to_string(first + 1) + "-" + std::to_string(last) +
               " of " + std::to_string(names.size()) + ", ranked by " + ranked_by + "; the rest in";
      for (std::size_t other = 0; other < pages; ++other)
        if (other != page) title += " " + PageFile(f.stem, other);
    }
    gp << "set output '" << PageFile(f.stem, page) << "'\n"
       << "set title \"" << title << "\"\n"
       << "set ylabel " << Quoted(f.ylabel) << "\n"
       << "plot ";
    for (std::size_t i = first; i < last; ++i) {
      const std::string condition =
          "strcol(1) eq " + Quoted(names[i]) + (f.keep.empty() ? "" : " && " + f.keep);
      gp << (i == first ? "" : ", \\\n     ") << "'" << f.csv << "' using ($2*100):(" << condition
         << " ? " << f.y << " : 1/0) title " << Quoted(names[i]);
    }
    gp << "\n";
    pngs->push_back(PageFile(f.stem, page));
  }
}

std::vector<std::string> SplitCsvLine(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream row(line);
  for (std::string cell; std::getline(row, cell, ',');) cells.push_back(cell);
  return cells;
}

// The shell word for `s`: single-quoted, its own single quotes spelled '\''.
std::string ShellWord(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

}  // namespace

PlotScript MakePlotScript(const std::vector<PlotSeries>& configs,
                          const std::vector<std::string>& swept, int scenes) {
  // The most telling first: most true positives at 8 cm, then fewest false ones, then file
  // order.
  std::vector<PlotSeries> ranked = configs;
  std::stable_sort(ranked.begin(), ranked.end(), [](const PlotSeries& a, const PlotSeries& b) {
    return a.tp != b.tp ? a.tp > b.tp : a.fp < b.fp;
  });
  std::vector<std::string> names;
  for (const PlotSeries& s : ranked) names.push_back(s.name);
  const std::string of = std::to_string(scenes) + (scenes == 1 ? " scene" : " scenes");

  PlotScript script;
  std::ostringstream gp;
  gp << "# gnuplot script written by saccade eval; run: gnuplot plot.gp (in this folder)\n"
        "set datafile separator ','\n"
        "set terminal pngcairo size 1000,680 noenhanced font ',11'\n"
        "set grid\n"
        "set key below horizontal  # under the axes: the legend never hides a curve\n"
        "set style data linespoints\n"
        "set offsets 0, 0, graph 0.05, 0\n\n"
        "# True and false positives as the distance threshold grows (the paper's Figs. 8, 9).\n"
        "set xlabel 'distance threshold (cm)'\n"
        "set xrange [0:10.5]\n"
        "set arrow 1 from 8, graph 0 to 8, graph 1 nohead dashtype 2 linecolor 'gray40'\n"
        "set yrange [0:"
     << std::max(1, scenes) << "]\n";
  const std::string ranked_by = "true positives at 8 cm";
  AddPages(
      {"thresholds_tp",
       "True positives against the distance threshold (" + of + "; dashed: the paper's 8 cm rule)",
       "true positives (scenes)", "thresholds.csv", "$3", ""},
      names, ranked_by, gp, &script.pngs);
  gp << "set yrange [0:*]\n";
  AddPages(
      {"thresholds_fp",
       "False positives against the distance threshold (" + of + "; dashed: the paper's 8 cm rule)",
       "false positives (detections)", "thresholds.csv", "$4", ""},
      names, ranked_by, gp, &script.pngs);
  if (!swept.empty()) {
    gp << "\n# The fovea moved off the object along x (the paper's Fig. 10), one frame and the "
          "attention loop.\n"
          "unset arrow 1\n"
          "set xlabel 'fovea distance from the object, along x (cm)'\n"
          "set xrange [*:*]\n"
          "set yrange [0:"
       << std::max(1, scenes) << "]\n";
    AddPages(
        {"sweep", "True positives in one frame with the fovea moved off the object (" + of + ")",
         "true positives (scenes)", "sweep.csv", "$3", ""},
        swept, "file order", gp, &script.pngs);
    gp << "set yrange [0:*]\n";
    AddPages({"sweep_attention",
              "Frames the attention loop takes to find the object from there (" + of + ")",
              "frames until found (mean over the scenes found)", "sweep.csv", "$7", "$6 > 0"},
             swept, "file order", gp, &script.pngs);
  }
  script.text = gp.str();
  return script;
}

bool WritePlots(const fs::path& dir, std::vector<std::string>* pngs, std::string* error) {
  const auto fail = [&](const std::string& why) {
    *error = why;
    return false;
  };
  // table.csv: name,pipeline,mean_ms,tp,fp,tp_sphere,fp_sphere,frames,...
  std::ifstream table(dir / "table.csv");
  std::string line;
  if (!table || !std::getline(table, line) || line.rfind("name,pipeline,mean_ms,tp,fp,", 0) != 0)
    return fail((dir / "table.csv").string() + ": missing, or not saccade eval's table");
  std::vector<PlotSeries> configs;
  int scenes = 0;
  for (int row = 2; std::getline(table, line); ++row) {
    const std::vector<std::string> cells = SplitCsvLine(line);
    try {
      if (cells.size() < 8) throw std::invalid_argument("short row");
      configs.push_back({cells[0], std::stoi(cells[3]), std::stoi(cells[4])});
      scenes = std::max(scenes, std::stoi(cells[7]));
    } catch (const std::exception&) {
      return fail((dir / "table.csv").string() + ": line " + std::to_string(row) +
                  ": expected name,pipeline,mean_ms,tp,fp,tp_sphere,fp_sphere,frames");
    }
  }
  if (configs.empty()) return fail((dir / "table.csv").string() + ": no configuration");
  std::vector<std::string> swept;  // sweep.csv's names, in order
  std::ifstream sweep(dir / "sweep.csv");
  if (sweep && std::getline(sweep, line))
    while (std::getline(sweep, line)) {
      const std::string name = line.substr(0, line.find(','));
      if (std::find(swept.begin(), swept.end(), name) == swept.end()) swept.push_back(name);
    }

  const PlotScript script = MakePlotScript(configs, swept, scenes);
  // The plots of an earlier run (another number of pages, a sweep) are not left to mislead.
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (entry.path().extension() == ".png" &&
        (name.rfind("thresholds_tp", 0) == 0 || name.rfind("thresholds_fp", 0) == 0 ||
         name.rfind("sweep", 0) == 0))
      fs::remove(entry.path(), ec);
  }
  if (!WriteBytes((dir / "plot.gp").string(), script.text, error)) return false;
  const std::string command = "cd " + ShellWord(dir.string()) + " && gnuplot plot.gp 2> plot.log";
  if (std::system(command.c_str()) != 0)
    return fail("gnuplot failed (see " + (dir / "plot.log").string() + ")");
  *pngs = script.pngs;
  return true;
}

}  // namespace saccade::eval
