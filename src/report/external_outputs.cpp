#include "external_outputs.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <system_error>
#include <thread>

#include "child_process.hpp"
#include "hrgbench/session/session.hpp"

namespace hrgbench::report::internal {
namespace {

using nlohmann::json;

// A figure of 2000 points per series is ~150 KB of SVG; anything far beyond is not read.
constexpr std::uintmax_t kMaxSvgBytes = std::uintmax_t{64} << 20;

// A gnuplot single-quoted string: no escapes inside, a quote is doubled.
std::string Quoted(const std::string& text) {
  std::string out = "'";
  for (const char c : text) {
    if (c == '\'')
      out += "''";
    else if (c == '\n')
      out += ' ';
    else
      out += c;
  }
  return out + "'";
}

double ValueOf(const json& v) { return v.is_number() ? v.get<double>() : std::nan(""); }

void WriteNumber(std::ostream& out, double v) {
  if (std::isfinite(v))
    out << v;
  else
    out << "NaN";
}

// Writes the data files of one figure and appends its commands to `script`. False when the figure
// has nothing to plot.
bool FigureScript(const json& f, const std::string& tmp, std::ostream& script) {
  const std::string name = f.value("name", "");
  const json& series = f["series"];
  if (name.empty() || !series.is_array() || series.empty()) return false;
  const bool bar = f.value("type", "") == "bar";
  const bool square = f.value("equal_aspect", false);
  script << "set terminal svg size " << (square ? "480,480" : "960,360")
         << " dynamic background rgb 'white' font 'sans,10' noenhanced\n"
         << "set output " << Quoted(tmp + "/" + name + ".svg") << "\n"
         << "set title " << Quoted(f.value("caption", name)) << " font 'sans,9'\n"
         << "set xlabel " << Quoted(f.value("x_label", "")) << "\n"
         << "set ylabel " << Quoted(f.value("y_label", "")) << "\n"
         << (square ? "set key below\n" : "set key outside right top\n")
         << "set grid\nunset logscale\nset size noratio\n"
         << "set xtics auto\nset ytics mirror\nunset y2tics\nunset y2label\n";
  if (f.value("y_log", false)) script << "set logscale y\n";
  if (f.value("x_log", false)) script << "set logscale x\n";
  // Series on the right-hand axis (the orbit's θ in degrees beside a and b).
  const auto on_right = [](const json& s) { return s.value("axis", "") == "y2"; };
  if (std::any_of(series.begin(), series.end(), on_right))
    script << "set ytics nomirror\nset y2tics\nset y2label " << Quoted(f.value("y2_label", ""))
           << "\n";
  if (square)
    script << "set size ratio -1\nset xrange [-1.1:1.1]\nset yrange [-1.1:1.1]\n";
  else
    script << "set autoscale xy\n";
  if (bar) {
    const std::string file = tmp + "/" + name + ".dat";
    std::ofstream out(file);
    const json& labels = f["labels"];
    for (std::size_t i = 0; i < labels.size(); ++i) {
      out << labels[i].get<std::string>();
      for (const json& s : series) {
        out << ' ';
        WriteNumber(out, i < s["y"].size() ? ValueOf(s["y"][i]) : std::nan(""));
      }
      out << '\n';
    }
    script << "plot ";
    for (std::size_t k = 0; k < series.size(); ++k)
      script << (k ? ", " : "") << Quoted(file) << " using 0:" << k + 2
             << (k == 0 ? ":xtic(1)" : "") << " with linespoints pt 7 title "
             << Quoted(series[k].value("label", ""));
    script << "\n";
    return true;
  }
  script << "plot ";
  for (std::size_t k = 0; k < series.size(); ++k) {
    const json& s = series[k];
    const json& xs = s.contains("x") ? s["x"] : f["x"];
    const json& ys = s["y"];
    const std::string file = tmp + "/" + name + "-" + std::to_string(k) + ".dat";
    std::ofstream out(file);
    out.precision(7);
    for (std::size_t i = 0; i < ys.size() && i < xs.size(); ++i) {
      WriteNumber(out, ValueOf(xs[i]));
      out << ' ';
      WriteNumber(out, ValueOf(ys[i]));
      out << '\n';
    }
    script << (k ? ", " : "") << Quoted(file) << " using 1:2" << (on_right(s) ? " axes x1y2" : "")
           << (s.value("points", false) ? " with linespoints pt 7 lw 1 dt "
                                        : " with lines lw 1 dt ")
           << (s.value("model", false) ? 2 : 1) << " title " << Quoted(s.value("label", ""));
  }
  script << "\n";
  return true;
}

}  // namespace

FiguresResult WriteGnuplotFigures(const json& data, const std::filesystem::path& out_dir,
                                  double timeout_s) {
  FiguresResult result;
  const std::string tmp = MakeTemporaryDirectory("hrg-report-figures-");
  if (tmp.empty()) {
    result.warnings.push_back("figures not drawn: no temporary directory");
    return result;
  }
  // The figures split over one gnuplot per core (each draws its share; they are independent).
  const std::size_t processes = std::clamp<std::size_t>(std::thread::hardware_concurrency(), 1, 4);
  std::vector<std::vector<std::string>> share(processes);
  {
    std::vector<std::ofstream> scripts;
    for (std::size_t p = 0; p < processes; ++p) {
      scripts.emplace_back(tmp + "/figures-" + std::to_string(p) + ".gp");
      scripts.back() << "set encoding utf8\nset datafile missing 'NaN'\n";
    }
    std::size_t next = 0;
    for (const json& f : data["figures"]) {
      if (FigureScript(f, tmp, scripts[next % processes])) {
        share[next % processes].push_back(f.value("name", ""));
        ++next;
      }
    }
    for (std::ofstream& script : scripts) script << "unset output\n";
  }
  std::vector<ChildResult> runs(processes);
  {
    std::vector<std::thread> threads;
    for (std::size_t p = 0; p < processes; ++p)
      threads.emplace_back([&, p] {
        runs[p] = RunChild({"gnuplot", tmp + "/figures-" + std::to_string(p) + ".gp"}, timeout_s);
      });
    for (std::thread& t : threads) t.join();
  }
  std::vector<std::string> drawn;
  std::string failure;
  for (std::size_t p = 0; p < processes; ++p) {
    if (!runs[p].started || runs[p].exit_code != 0) {
      if (failure.empty()) failure = runs[p].Describe("gnuplot");
    } else {
      drawn.insert(drawn.end(), share[p].begin(), share[p].end());
    }
  }
  if (!failure.empty())
    result.warnings.push_back("figures for documents (SVG) not drawn: " + failure);
  {
    // In the page's order.
    for (const json& f : data["figures"]) {
      const std::string name = f.value("name", "");
      if (std::find(drawn.begin(), drawn.end(), name) == drawn.end()) continue;
      const std::string drawn_svg = tmp + "/" + name + ".svg";
      std::error_code size_error;
      const std::uintmax_t size = std::filesystem::file_size(drawn_svg, size_error);
      if (!size_error && size > kMaxSvgBytes) {
        result.warnings.push_back("figure " + name + ": gnuplot wrote " + std::to_string(size) +
                                  " bytes, over the 64 MiB a figure may have");
        continue;
      }
      std::ifstream in(drawn_svg, std::ios::binary);
      std::stringstream text;
      text << in.rdbuf();
      const std::filesystem::path target = out_dir / (name + ".svg");
      if (text.str().empty()) {
        result.warnings.push_back("figure " + name + ": gnuplot wrote nothing");
      } else if (auto written = session::WriteFileAtomic(target, text.str()); !written) {
        result.warnings.push_back("figure " + name + ": " + written.error().ToString());
      } else {
        result.written.push_back(target);
      }
    }
  }
  std::error_code ec;
  std::filesystem::remove_all(tmp, ec);
  return result;
}

std::string PrintPdf(const std::string& chromium, const std::filesystem::path& html,
                     const std::filesystem::path& pdf, double timeout_s) {
  const std::string tmp = MakeTemporaryDirectory("hrg-report-chromium-");
  if (tmp.empty()) return "no temporary directory for Chromium's profile";
  const std::filesystem::path partial =
      pdf.parent_path() / ("." + pdf.filename().string() + ".tmp");
  std::error_code ec;
  const std::filesystem::path absolute = std::filesystem::absolute(html, ec);
  const ChildResult run =
      RunChild({chromium, "--headless", "--no-sandbox", "--disable-gpu", "--no-first-run",
                "--user-data-dir=" + tmp, "--no-pdf-header-footer",
                "--print-to-pdf=" + partial.string(), "file://" + absolute.string()},
               timeout_s);
  std::filesystem::remove_all(tmp, ec);
  std::string why;
  if (!run.started || run.exit_code != 0) {
    why = run.Describe(chromium);
  } else if (std::filesystem::file_size(partial, ec) == 0 || ec) {
    why = chromium + " wrote no PDF";
  } else {
    std::filesystem::rename(partial, pdf, ec);
    if (ec) why = "cannot move the PDF into place: " + ec.message();
  }
  if (!why.empty()) std::filesystem::remove(partial, ec);
  return why;
}

}  // namespace hrgbench::report::internal
