// par2d_image_diff: error metrics between two PFM images; exit 1 when a pixel differs by more than --tolerance.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "par2d/image_io.hpp"

namespace {

int fail(const std::string& message) {
  std::fprintf(stderr, "par2d_image_diff: %s\n", message.c_str());
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Compares two PFM color images channel by channel. Prints the max and mean absolute "
      "difference, the RMSE and how many pixels have a channel differing by more than the "
      "tolerance. Exit status: 0 within tolerance, 1 over it, 2 on errors.",
      "par2d_image_diff"};
  std::string path_a, path_b;
  double tolerance = 0.0;
  bool json = false;
  app.add_option("a", path_a, "First PFM image")->required();
  app.add_option("b", path_b, "Second PFM image")->required();
  app.add_option("--tolerance", tolerance,
                 "Largest allowed absolute difference per channel (linear units). Default: 0")
      ->check(CLI::Range(0.0, 1e300));
  app.add_flag("--json", json, "Print one JSON object instead of a line");
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    return fail(e.what());
  }

  int wa = 0, ha = 0, wb = 0, hb = 0;
  std::vector<float> a, b;
  if (par2d::Status s = par2d::read_pfm(path_a, wa, ha, a); !s) return fail(s.message());
  if (par2d::Status s = par2d::read_pfm(path_b, wb, hb, b); !s) return fail(s.message());
  if (wa != wb || ha != hb)
    return fail("size mismatch: " + std::to_string(wa) + "x" + std::to_string(ha) + " vs " +
                std::to_string(wb) + "x" + std::to_string(hb));

  double max_abs = 0.0, sum_abs = 0.0, sum_sq = 0.0;
  long long over = 0;
  int worst_i = 0, worst_j = 0;
  for (int j = 0; j < ha; ++j) {
    for (int i = 0; i < wa; ++i) {
      bool pixel_over = false;
      for (int c = 0; c < 3; ++c) {
        const std::size_t k = (static_cast<std::size_t>(j) * wa + i) * 3 + c;
        const double x = a[k], y = b[k];
        double d;
        if (std::isnan(x) || std::isnan(y))
          d = std::isnan(x) && std::isnan(y) ? 0.0 : INFINITY;  // NaN on one side only is a failure
        else
          d = std::fabs(x - y);
        if (d > max_abs) {
          max_abs = d;
          worst_i = i;
          worst_j = j;
        }
        sum_abs += d;
        sum_sq += d * d;
        if (d > tolerance) pixel_over = true;
      }
      if (pixel_over) ++over;
    }
  }
  const double n = 3.0 * wa * ha;
  const double mean_abs = sum_abs / n, rmse = std::sqrt(sum_sq / n);
  if (json) {
    std::printf(
        "{\"max_abs\": %.9g, \"mean_abs\": %.9g, \"rmse\": %.9g, \"pixels_over\": %lld, "
        "\"tolerance\": %.9g, \"pixels\": %lld, \"worst_x\": %d, \"worst_y\": %d}\n",
        std::isfinite(max_abs) ? max_abs : 1e308, std::isfinite(mean_abs) ? mean_abs : 1e308,
        std::isfinite(rmse) ? rmse : 1e308, over, tolerance, static_cast<long long>(wa) * ha,
        worst_i, worst_j);
  } else {
    std::printf("max_abs=%.9g mean_abs=%.9g rmse=%.9g pixels_over=%lld/%lld tolerance=%.9g worst=(%d,%d)\n",
                max_abs, mean_abs, rmse, over, static_cast<long long>(wa) * ha, tolerance, worst_i,
                worst_j);
  }
  return over > 0 ? 1 : 0;
}
