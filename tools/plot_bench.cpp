// Plots bench_scaling results (Google Benchmark JSON) as a PNG: frame time against occluder and light count.
//
// Usage: par2d_plot_bench BENCH.json OUT.png
// BENCH.json is the output of `par2d_bench --benchmark_filter=^scaling/ --benchmark_out=BENCH.json`
// (or --benchmark_format=json on stdout). Text is drawn with a hand-coded 5x7 bitmap font so the
// tool needs nothing beyond nlohmann_json and stb_image_write.
#include <stb_image_write.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

namespace {

// ---------------------------------------------------------------------------------------------
// 5x7 bitmap font: each glyph is 7 rows of 5 columns, '#' set. Lowercase letters are drawn as
// uppercase; characters without a glyph are drawn as '?'.
struct Glyph {
  char ch;
  const char* rows[7];
};

constexpr Glyph kFont[] = {
    {' ', {".....", ".....", ".....", ".....", ".....", ".....", "....."}},
    {'0', {".###.", "#...#", "#..##", "#.#.#", "##..#", "#...#", ".###."}},
    {'1', {"..#..", ".##..", "..#..", "..#..", "..#..", "..#..", ".###."}},
    {'2', {".###.", "#...#", "....#", "...#.", "..#..", ".#...", "#####"}},
    {'3', {"#####", "...#.", "..#..", "...#.", "....#", "#...#", ".###."}},
    {'4', {"...#.", "..##.", ".#.#.", "#..#.", "#####", "...#.", "...#."}},
    {'5', {"#####", "#....", "####.", "....#", "....#", "#...#", ".###."}},
    {'6', {"..##.", ".#...", "#....", "####.", "#...#", "#...#", ".###."}},
    {'7', {"#####", "....#", "...#.", "..#..", ".#...", ".#...", ".#..."}},
    {'8', {".###.", "#...#", "#...#", ".###.", "#...#", "#...#", ".###."}},
    {'9', {".###.", "#...#", "#...#", ".####", "....#", "...#.", ".##.."}},
    {'A', {".###.", "#...#", "#...#", "#####", "#...#", "#...#", "#...#"}},
    {'B', {"####.", "#...#", "#...#", "####.", "#...#", "#...#", "####."}},
    {'C', {".###.", "#...#", "#....", "#....", "#....", "#...#", ".###."}},
    {'D', {"###..", "#..#.", "#...#", "#...#", "#...#", "#..#.", "###.."}},
    {'E', {"#####", "#....", "#....", "####.", "#....", "#....", "#####"}},
    {'F', {"#####", "#....", "#....", "####.", "#....", "#....", "#...."}},
    {'G', {".###.", "#...#", "#....", "#.###", "#...#", "#...#", ".####"}},
    {'H', {"#...#", "#...#", "#...#", "#####", "#...#", "#...#", "#...#"}},
    {'I', {".###.", "..#..", "..#..", "..#..", "..#..", "..#..", ".###."}},
    {'J', {"..###", "...#.", "...#.", "...#.", "...#.", "#..#.", ".##.."}},
    {'K', {"#...#", "#..#.", "#.#..", "##...", "#.#..", "#..#.", "#...#"}},
    {'L', {"#....", "#....", "#....", "#....", "#....", "#....", "#####"}},
    {'M', {"#...#", "##.##", "#.#.#", "#.#.#", "#...#", "#...#", "#...#"}},
    {'N', {"#...#", "#...#", "##..#", "#.#.#", "#..##", "#...#", "#...#"}},
    {'O', {".###.", "#...#", "#...#", "#...#", "#...#", "#...#", ".###."}},
    {'P', {"####.", "#...#", "#...#", "####.", "#....", "#....", "#...."}},
    {'Q', {".###.", "#...#", "#...#", "#...#", "#.#.#", "#..#.", ".##.#"}},
    {'R', {"####.", "#...#", "#...#", "####.", "#.#..", "#..#.", "#...#"}},
    {'S', {".####", "#....", "#....", ".###.", "....#", "....#", "####."}},
    {'T', {"#####", "..#..", "..#..", "..#..", "..#..", "..#..", "..#.."}},
    {'U', {"#...#", "#...#", "#...#", "#...#", "#...#", "#...#", ".###."}},
    {'V', {"#...#", "#...#", "#...#", "#...#", "#...#", ".#.#.", "..#.."}},
    {'W', {"#...#", "#...#", "#...#", "#.#.#", "#.#.#", "#.#.#", ".#.#."}},
    {'X', {"#...#", "#...#", ".#.#.", "..#..", ".#.#.", "#...#", "#...#"}},
    {'Y', {"#...#", "#...#", ".#.#.", "..#..", "..#..", "..#..", "..#.."}},
    {'Z', {"#####", "....#", "...#.", "..#..", ".#...", "#....", "#####"}},
    {':', {".....", ".##..", ".##..", ".....", ".##..", ".##..", "....."}},
    {'.', {".....", ".....", ".....", ".....", ".....", ".##..", ".##.."}},
    {',', {".....", ".....", ".....", ".....", ".##..", "..#..", ".#..."}},
    {'-', {".....", ".....", ".....", "#####", ".....", ".....", "....."}},
    {'+', {".....", "..#..", "..#..", "#####", "..#..", "..#..", "....."}},
    {'=', {".....", ".....", "#####", ".....", "#####", ".....", "....."}},
    {'/', {".....", "....#", "...#.", "..#..", ".#...", "#....", "....."}},
    {'(', {"...#.", "..#..", ".#...", ".#...", ".#...", "..#..", "...#."}},
    {')', {".#...", "..#..", "...#.", "...#.", "...#.", "..#..", ".#..."}},
    {'<', {"...#.", "..#..", ".#...", "#....", ".#...", "..#..", "...#."}},
    {'>', {".#...", "..#..", "...#.", "....#", "...#.", "..#..", ".#..."}},
    {'%', {"##...", "##..#", "...#.", "..#..", ".#...", "#..##", "...##"}},
    {'_', {".....", ".....", ".....", ".....", ".....", ".....", "#####"}},
    {'~', {".....", ".....", ".#...", "#.#.#", "...#.", ".....", "....."}},
    {'?', {".###.", "#...#", "....#", "...#.", "..#..", ".....", "..#.."}},
};

const Glyph& glyph_for(char c) {
  const char upper = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  for (const Glyph& g : kFont) {
    if (g.ch == upper) return g;
  }
  return kFont[sizeof(kFont) / sizeof(kFont[0]) - 1];  // '?'
}

constexpr int kGlyphAdvance = 6;  // 5 columns + 1 column of spacing, in font pixels
constexpr int kGlyphHeight = 7;

// ---------------------------------------------------------------------------------------------
using Rgb8 = std::array<uint8_t, 3>;

constexpr Rgb8 kWhite{255, 255, 255};
constexpr Rgb8 kBlack{20, 20, 20};
constexpr Rgb8 kGrid{225, 225, 225};
constexpr Rgb8 kMinorGrid{242, 242, 242};
constexpr Rgb8 kMuted{110, 110, 110};
constexpr Rgb8 kCulledColor{31, 119, 180};     // blue
constexpr Rgb8 kUnculledColor{230, 110, 10};   // orange

class Canvas {
 public:
  Canvas(int width, int height) : width_(width), height_(height), pixels_(static_cast<size_t>(width) * height * 3, 255) {}

  int width() const { return width_; }
  int height() const { return height_; }
  const uint8_t* data() const { return pixels_.data(); }

  // Blends `color` over the pixel with coverage `alpha` in [0, 1]; off-canvas writes are dropped.
  void blend(int x, int y, Rgb8 color, double alpha = 1.0) {
    if (x < 0 || y < 0 || x >= width_ || y >= height_ || alpha <= 0.0) return;
    alpha = std::min(alpha, 1.0);
    uint8_t* p = &pixels_[(static_cast<size_t>(y) * width_ + x) * 3];
    for (int c = 0; c < 3; ++c) p[c] = static_cast<uint8_t>(std::lround(p[c] + (color[c] - p[c]) * alpha));
  }

  void fill_rect(int x0, int y0, int x1, int y1, Rgb8 color) {
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) blend(x, y, color);
  }

  // A line of width `thickness`, antialiased by distance to the segment (plots are small enough
  // that the brute-force bounding-box scan costs nothing).
  void line(double ax, double ay, double bx, double by, Rgb8 color, double thickness) {
    const double r = 0.5 * thickness;
    const int x0 = static_cast<int>(std::floor(std::min(ax, bx) - r - 1)), x1 = static_cast<int>(std::ceil(std::max(ax, bx) + r + 1));
    const int y0 = static_cast<int>(std::floor(std::min(ay, by) - r - 1)), y1 = static_cast<int>(std::ceil(std::max(ay, by) + r + 1));
    const double dx = bx - ax, dy = by - ay, len2 = dx * dx + dy * dy;
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        const double px = x + 0.5 - ax, py = y + 0.5 - ay;
        const double t = len2 > 0 ? std::clamp((px * dx + py * dy) / len2, 0.0, 1.0) : 0.0;
        const double d = std::hypot(px - t * dx, py - t * dy);
        blend(x, y, color, r + 0.5 - d);
      }
    }
  }

  void disc(double cx, double cy, double radius, Rgb8 color) { line(cx, cy, cx, cy, color, 2.0 * radius); }

  // Draws `text` with its top-left corner at (x, y), each font pixel `scale` canvas pixels.
  void text(int x, int y, const std::string& s, Rgb8 color, int scale) {
    for (const char c : s) {
      const Glyph& g = glyph_for(c);
      for (int row = 0; row < kGlyphHeight; ++row)
        for (int col = 0; col < 5; ++col)
          if (g.rows[row][col] == '#') fill_rect(x + col * scale, y + row * scale, x + (col + 1) * scale, y + (row + 1) * scale, color);
      x += kGlyphAdvance * scale;
    }
  }

  static int text_width(const std::string& s, int scale) {
    return s.empty() ? 0 : (static_cast<int>(s.size()) * kGlyphAdvance - 1) * scale;
  }

 private:
  int width_;
  int height_;
  std::vector<uint8_t> pixels_;
};

// ---------------------------------------------------------------------------------------------
// One measured point of the scaling suite.
struct Key {
  std::string sweep;  // occluder_sweep, light_sweep, target
  int occluders = 0;
  int lights = 0;
  bool culled = true;
  bool operator<(const Key& o) const {
    return std::tie(sweep, occluders, lights, culled) < std::tie(o.sweep, o.occluders, o.lights, o.culled);
  }
};

struct Results {
  std::map<Key, std::vector<double>> times_ms;  // every iteration run of the point
  std::map<Key, double> aggregate_ms;           // a median/mean aggregate, when only those exist
  std::vector<Key> skipped;
  std::string label;  // e.g. "avx512, 2 threads"
};

[[noreturn]] void fail(const std::string& message) { throw std::runtime_error(message); }

double to_ms(double value, const std::string& unit) {
  if (unit == "ns") return value * 1e-6;
  if (unit == "us") return value * 1e-3;
  if (unit == "ms") return value;
  if (unit == "s") return value * 1e3;
  fail("unknown time_unit \"" + unit + "\"");
}

int parse_count(const std::string& token, const std::string& name) {
  const std::string digits = token.substr(token.find(':') + 1);
  if (digits.empty() || digits.size() > 9 || !std::all_of(digits.begin(), digits.end(), ::isdigit)) fail("bad count in benchmark name \"" + name + "\"");
  return std::stoi(digits);
}

Results read_results(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path + ": cannot open");
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    fail(path + ": not valid JSON (" + std::string(e.what()) + ")");
  }
  if (!doc.is_object() || !doc.contains("benchmarks") || !doc["benchmarks"].is_array())
    fail(path + ": no \"benchmarks\" array; expected Google Benchmark JSON (--benchmark_format=json)");

  Results results;
  for (size_t i = 0; i < doc["benchmarks"].size(); ++i) {
    const nlohmann::json& b = doc["benchmarks"][i];
    const std::string where = path + ": benchmarks[" + std::to_string(i) + "]";
    if (!b.is_object() || !b.contains("name") || !b["name"].is_string()) fail(where + ": no name");
    const std::string name = b["name"].get<std::string>();
    if (name.rfind("scaling/", 0) != 0) continue;  // other suites may share the file

    std::vector<std::string> tokens;
    std::stringstream ss(name);
    for (std::string t; std::getline(ss, t, '/');) tokens.push_back(t);
    Key key;
    if (tokens.size() < 2) fail(where + ": cannot parse name \"" + name + "\"");
    key.sweep = tokens[1];
    bool has_occ = false, has_lights = false, has_mode = false, skipped = false;
    for (const std::string& t : tokens) {
      if (t.rfind("occluders:", 0) == 0) key.occluders = parse_count(t, name), has_occ = true;
      else if (t.rfind("lights:", 0) == 0) key.lights = parse_count(t, name), has_lights = true;
      else if (t == "culled" || t == "unculled") key.culled = t == "culled", has_mode = true;
      else if (t.rfind("skipped", 0) == 0) skipped = true;
    }
    if (!has_occ || !has_lights || !has_mode) fail(where + ": cannot parse name \"" + name + "\"");
    if (key.occluders <= 0 || key.lights <= 0) fail(where + ": counts must be positive in \"" + name + "\"");

    if (skipped || (b.contains("error_occurred") && b["error_occurred"].is_boolean() && b["error_occurred"].get<bool>())) {
      results.skipped.push_back(key);
      continue;
    }
    if (!b.contains("real_time") || !b["real_time"].is_number() || !b.contains("time_unit") || !b["time_unit"].is_string())
      fail(where + ": no real_time/time_unit");
    const double ms = to_ms(b["real_time"].get<double>(), b["time_unit"].get<std::string>());
    if (!(ms > 0.0) || !std::isfinite(ms)) fail(where + ": real_time must be positive");
    const std::string run_type = b.value("run_type", std::string("iteration"));
    if (run_type == "aggregate") {
      const std::string agg = b.value("aggregate_name", std::string());
      if (agg == "median" || (agg == "mean" && !results.aggregate_ms.count(key))) results.aggregate_ms[key] = ms;
    } else {
      results.times_ms[key].push_back(ms);
    }
    if (results.label.empty() && b.contains("label") && b["label"].is_string()) results.label = b["label"].get<std::string>();
  }
  return results;
}

// Median of the iteration runs of a point (robust to a noisy repetition), else its aggregate.
bool point_ms(const Results& r, const Key& key, double& ms) {
  const auto it = r.times_ms.find(key);
  if (it != r.times_ms.end() && !it->second.empty()) {
    std::vector<double> v = it->second;
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    ms = n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
    return true;
  }
  const auto agg = r.aggregate_ms.find(key);
  if (agg == r.aggregate_ms.end()) return false;
  ms = agg->second;
  return true;
}

struct Series {
  std::vector<std::pair<int, double>> points;  // (count, ms), sorted by count
};

// The culled [0] and unculled [1] series of a sweep; the swept count is occluders or lights.
std::array<Series, 2> sweep_series(const Results& r, const std::string& sweep, bool by_occluders) {
  std::array<Series, 2> out;
  std::map<Key, bool> seen;
  auto collect = [&](const Key& k) {
    if (k.sweep != sweep || seen.count(k)) return;
    seen[k] = true;
    double ms = 0;
    if (point_ms(r, k, ms)) out[k.culled ? 0 : 1].points.push_back({by_occluders ? k.occluders : k.lights, ms});
  };
  for (const auto& kv : r.times_ms) collect(kv.first);
  for (const auto& kv : r.aggregate_ms) collect(kv.first);
  for (Series& s : out) std::sort(s.points.begin(), s.points.end());
  return out;
}

std::string format_ms(double ms) {
  char buf[32];
  if (ms >= 100) std::snprintf(buf, sizeof buf, "%.0f", ms);
  else if (ms >= 10) std::snprintf(buf, sizeof buf, "%.1f", ms);
  else std::snprintf(buf, sizeof buf, "%.2f", ms);
  return buf;
}

std::string format_tick(double v) {
  char buf[32];
  if (v >= 1) std::snprintf(buf, sizeof buf, "%.0f", v);
  else std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

// ---------------------------------------------------------------------------------------------
struct Panel {
  int x0, y0, x1, y1;  // plot area, canvas pixels
  double lx0, lx1;     // log2(count) range
  double ly0, ly1;     // log10(ms) range
  double px(double count) const { return x0 + (std::log2(count) - lx0) / (lx1 - lx0) * (x1 - x0); }
  double py(double ms) const { return y1 - (std::log10(ms) - ly0) / (ly1 - ly0) * (y1 - y0); }
};

void draw_panel(Canvas& c, const Panel& p, const std::string& title, const std::string& x_label,
                const std::array<Series, 2>& series, int skipped_unculled) {
  constexpr int kText = 2;
  // Grid: decades of ms with 2x and 5x minor lines; every power of two of the count.
  for (int d = static_cast<int>(std::floor(p.ly0)); d <= static_cast<int>(std::ceil(p.ly1)); ++d) {
    for (const double m : {1.0, 2.0, 5.0}) {
      const double v = m * std::pow(10.0, d);
      const double lv = std::log10(v);
      if (lv < p.ly0 - 1e-9 || lv > p.ly1 + 1e-9) continue;
      const int y = static_cast<int>(std::lround(p.py(v)));
      c.fill_rect(p.x0, y, p.x1 + 1, y + 1, m == 1.0 ? kGrid : kMinorGrid);
      const std::string label = format_tick(v);
      const int scale = m == 1.0 ? kText : 1;
      c.text(p.x0 - 8 - Canvas::text_width(label, scale), y - kGlyphHeight * scale / 2, label, m == 1.0 ? kBlack : kMuted, scale);
    }
  }
  for (int e = static_cast<int>(std::ceil(p.lx0)); e <= static_cast<int>(std::floor(p.lx1)); ++e) {
    const int x = static_cast<int>(std::lround(p.px(std::ldexp(1.0, e))));
    c.fill_rect(x, p.y0, x + 1, p.y1 + 1, e % 2 == 0 ? kGrid : kMinorGrid);
    if (e % 2 == 0) {
      const std::string label = std::to_string(1 << e);
      c.text(x - Canvas::text_width(label, kText) / 2, p.y1 + 10, label, kBlack, kText);
    }
  }
  // Axes frame.
  c.fill_rect(p.x0, p.y0, p.x0 + 2, p.y1 + 2, kBlack);
  c.fill_rect(p.x0, p.y1, p.x1 + 1, p.y1 + 2, kBlack);
  c.text((p.x0 + p.x1 - Canvas::text_width(title, kText)) / 2, p.y0 - 28, title, kBlack, kText);
  c.text((p.x0 + p.x1 - Canvas::text_width(x_label, kText)) / 2, p.y1 + 34, x_label, kBlack, kText);
  c.text(p.x0 - 70, p.y0 - 28, "MS", kMuted, kText);

  // Lines, markers and each point's value.
  for (int s = 0; s < 2; ++s) {
    const Rgb8 color = s == 0 ? kCulledColor : kUnculledColor;
    const auto& pts = series[s].points;
    for (size_t i = 0; i + 1 < pts.size(); ++i)
      c.line(p.px(pts[i].first), p.py(pts[i].second), p.px(pts[i + 1].first), p.py(pts[i + 1].second), color, 3.0);
    for (const auto& [count, ms] : pts) {
      c.disc(p.px(count), p.py(ms), 5.0, color);
      const std::string v = format_ms(ms);
      // Culled values below the marker, unculled above, so the two lines' labels rarely collide.
      const int ty = s == 0 ? static_cast<int>(p.py(ms)) + 9 : static_cast<int>(p.py(ms)) - 9 - kGlyphHeight;
      c.text(static_cast<int>(p.px(count)) - Canvas::text_width(v, 1) / 2, ty, v, color, 1);
    }
  }

  // Legend, bottom right inside the plot area: frame time grows with the count, so the lines
  // start low on the left and end high on the right, and this corner is the one they avoid.
  const std::string unculled = skipped_unculled > 0 ? "UNCULLED (" + std::to_string(skipped_unculled) + " SKIPPED: >3 S)" : "UNCULLED";
  const int box_w = 44 + std::max(Canvas::text_width("CULLED", kText), Canvas::text_width(unculled, kText)) + 14;
  const int lx = p.x1 - box_w - 4, ly = p.y1 - 56;
  c.fill_rect(lx - 6, ly - 6, lx + box_w, ly + 44, kWhite);
  for (int s = 0; s < 2; ++s) {
    const int y = ly + s * 22 + 7;
    const Rgb8 color = s == 0 ? kCulledColor : kUnculledColor;
    c.line(lx, y, lx + 32, y, color, 3.0);
    c.disc(lx + 16, y, 4.0, color);
    c.text(lx + 42, y - 7, s == 0 ? "CULLED" : unculled, kBlack, kText);
  }
}

// Log range covering `values`, widened to whole decades (ms) or padded (counts).
void value_range(const std::vector<double>& v, double& lo, double& hi) {
  lo = std::floor(std::log10(*std::min_element(v.begin(), v.end())));
  hi = std::ceil(std::log10(*std::max_element(v.begin(), v.end())));
  if (hi - lo < 1) hi = lo + 1;
}

void plot(const Results& r, const std::string& in_path, const std::string& out_path) {
  const auto occ = sweep_series(r, "occluder_sweep", true);
  const auto lights = sweep_series(r, "light_sweep", false);
  std::vector<double> all_ms;
  for (const auto* sweep : {&occ, &lights})
    for (const Series& s : *sweep)
      for (const auto& pt : s.points) all_ms.push_back(pt.second);
  if (all_ms.empty()) fail(in_path + ": no scaling/occluder_sweep or scaling/light_sweep results in the input (run par2d_bench --benchmark_filter=^scaling/)");

  Canvas c(1400, 640);
  double ly0 = 0, ly1 = 0;
  value_range(all_ms, ly0, ly1);  // one time axis for both panels, so they compare at a glance

  std::string title = "PAR2D FRAME TIME, 1920X1080";
  if (!r.label.empty()) title += " (" + r.label + ")";
  c.text((c.width() - Canvas::text_width(title, 3)) / 2, 16, title, kBlack, 3);

  auto count_range = [](const std::array<Series, 2>& s, double& lo, double& hi) {
    lo = 1e9, hi = -1e9;
    for (const Series& x : s)
      for (const auto& pt : x.points) lo = std::min(lo, std::log2(pt.first)), hi = std::max(hi, std::log2(pt.first));
    if (lo > hi) lo = 0, hi = 1;
    lo -= 0.5, hi += 0.5;
  };
  auto skipped_in = [&](const std::string& sweep) {
    return static_cast<int>(std::count_if(r.skipped.begin(), r.skipped.end(), [&](const Key& k) { return k.sweep == sweep && !k.culled; }));
  };

  Panel left{110, 100, 660, 520, 0, 0, ly0, ly1};
  count_range(occ, left.lx0, left.lx1);
  draw_panel(c, left, "OCCLUDER SWEEP, 16 LIGHTS", "OCCLUDERS", occ, skipped_in("occluder_sweep"));
  Panel right{800, 100, 1350, 520, 0, 0, ly0, ly1};
  count_range(lights, right.lx0, right.lx1);
  draw_panel(c, right, "LIGHT SWEEP, 256 OCCLUDERS", "LIGHTS", lights, skipped_in("light_sweep"));

  // Footer: the issue's target points, which sit on neither sweep's axis.
  std::string footer;
  for (const auto& kv : r.times_ms) {
    const Key& k = kv.first;
    double ms = 0;
    if (k.sweep != "target" || !point_ms(r, k, ms)) continue;
    footer += (footer.empty() ? "TARGETS (CULLED): " : ",  ") + std::to_string(k.lights) + " LIGHTS + " +
              std::to_string(k.occluders) + " OCCLUDERS = " + format_ms(ms) + " MS";
  }
  if (!footer.empty()) c.text((c.width() - Canvas::text_width(footer, 2)) / 2, 604, footer, kBlack, 2);

  // Written next to the destination and renamed, so a failed write leaves no partial PNG.
  const std::string tmp = out_path + ".tmp";
  if (!stbi_write_png(tmp.c_str(), c.width(), c.height(), 3, c.data(), c.width() * 3)) {
    std::remove(tmp.c_str());
    fail(out_path + ": cannot write PNG");
  }
  if (std::rename(tmp.c_str(), out_path.c_str()) != 0) {
    std::remove(tmp.c_str());
    fail(out_path + ": cannot write PNG");
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: par2d_plot_bench BENCH.json OUT.png\n");
    return 2;
  }
  try {
    plot(read_results(argv[1]), argv[1], argv[2]);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "par2d_plot_bench: %s\n", e.what());
    return 1;
  }
  return 0;
}
