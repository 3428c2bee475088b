// API misuse through par2d::render: every bad argument is an error status with a clear message, never a crash.
#include <doctest/doctest.h>

#include <cstdlib>
#include <string>
#include <vector>

#include "par2d/par2d.hpp"
#include "support/random_scenes.hpp"
#include "support/test_tiers.hpp"

namespace {

using namespace par2d;

Scene small_scene() {
  Scene s;
  s.width = 5;
  s.height = 4;
  s.view = {0, 0, 5, 4};
  Light l;
  l.shape = Circle{{1, 1}, 0.5};
  s.lights.push_back(l);
  s.occluders.push_back({Segment{{3, 0}, {3, 3}}});
  return s;
}

struct Buffer {
  std::vector<float> pixels;
  ImageView view;
  Buffer(int width, int height, std::ptrdiff_t stride) : pixels(static_cast<std::size_t>(stride) * height + 1, -7.0f) {
    view = {pixels.data(), width, height, stride};
  }
};

bool mentions(const Status& s, const char* word) { return s.message().find(word) != std::string::npos; }

}  // namespace

TEST_CASE("render refuses a null image with invalid_argument naming the data") {
  ImageView image{nullptr, 5, 4, 15};
  const Status s = render(small_scene(), {}, image);
  CHECK(s.code() == StatusCode::invalid_argument);
  CHECK(mentions(s, "null"));
}

TEST_CASE("render refuses a row stride below 3 * width, negative included, and writes nothing") {
  for (std::ptrdiff_t stride : {14, 5, 0, -15}) {
    Buffer b(5, 4, 15);
    b.view.row_stride = stride;
    const Status s = render(small_scene(), {}, b.view);
    INFO("stride ", stride, ": ", s.message());
    CHECK(s.code() == StatusCode::invalid_argument);
    CHECK(mentions(s, "row_stride"));
    for (float v : b.pixels) CHECK(v == -7.0f);
  }
}

TEST_CASE("a padded row stride renders and leaves the padding untouched" * par2d::test::per_isa()) {
  Buffer b(5, 4, 20);
  REQUIRE(render(small_scene(), {}, b.view).ok());
  for (int j = 0; j < 4; ++j)
    for (int k = 15; k < 20; ++k) CHECK(b.pixels[static_cast<std::size_t>(j) * 20 + k] == -7.0f);
  CHECK(b.pixels.back() == -7.0f);
}

TEST_CASE("render refuses an image whose size differs from the scene's, naming both sizes") {
  for (const std::pair<int, int>& size : {std::pair{4, 4}, std::pair{5, 3}, std::pair{6, 4}, std::pair{4, 5}}) {
    const int w = size.first, h = size.second;  // not a structured binding: INFO captures them (C++17)
    Buffer b(w, h, 3 * w);
    const Status s = render(small_scene(), {}, b.view);
    INFO(w, "x", h, ": ", s.message());
    CHECK(s.code() == StatusCode::invalid_argument);
    CHECK(mentions(s, (std::to_string(w) + "x" + std::to_string(h)).c_str()));
    CHECK(mentions(s, "5x4"));
  }
}

TEST_CASE("zero and negative sizes are refused as an invalid scene naming the side") {
  Scene s = small_scene();
  std::vector<float> pixels(3, 0.0f);
  s.width = 0;
  Status st = render(s, {}, ImageView{pixels.data(), 0, 4, 3});
  CHECK(st.code() == StatusCode::invalid_scene);
  CHECK(mentions(st, "width"));
  s = small_scene();
  s.height = -3;
  st = render(s, {}, ImageView{pixels.data(), 5, -3, 15});
  CHECK(st.code() == StatusCode::invalid_scene);
  CHECK(mentions(st, "height"));
  s = small_scene();
  s.width = kMaxImageSide + 1;
  st = render(s, {}, ImageView{pixels.data(), kMaxImageSide + 1, 4, 3 * (kMaxImageSide + 1)});
  CHECK(st.code() == StatusCode::invalid_scene);
  CHECK(mentions(st, "16384"));
}

TEST_CASE("negative threads, spp 0 or above 256, rays 0 are invalid_argument with the option named") {
  struct Case {
    RenderOptions options;
    const char* word;
  };
  std::vector<Case> cases;
  RenderOptions o;
  o.threads = -1;
  cases.push_back({o, "threads"});
  o = {};
  o.threads = -1000000;
  cases.push_back({o, "threads"});
  o = {};
  o.spp = 0;
  cases.push_back({o, "spp"});
  o = {};
  o.spp = 1000;
  cases.push_back({o, "spp"});
  o = {};
  o.spp = -4;
  cases.push_back({o, "spp"});
  o = {};
  o.backend = Backend::raycast;
  o.rays = 0;
  cases.push_back({o, "rays"});
  o.rays = (1 << 20) + 1;
  cases.push_back({o, "rays"});
  for (const Case& c : cases) {
    Buffer b(5, 4, 15);
    const Status s = render(small_scene(), c.options, b.view);
    INFO(c.word, ": ", s.message());
    CHECK(s.code() == StatusCode::invalid_argument);
    CHECK(mentions(s, c.word));
    CHECK(s.message().find('\n') == std::string::npos);
  }
}

TEST_CASE("an isa beyond the enum is invalid_argument") {
  for (const int value : {static_cast<int>(Isa::neon64) + 1, 9}) {
    RenderOptions o;
    o.backend = Backend::simd;
    o.isa = static_cast<Isa>(value);
    Buffer b(5, 4, 15);
    const Status s = render(small_scene(), o, b.view);
    INFO("isa value ", value);
    CHECK(s.code() == StatusCode::invalid_argument);
    CHECK(mentions(s, "isa"));
  }
}

TEST_CASE("an ISA this CPU lacks (e.g. another architecture's) renders at the best level it has") {
  for (const Isa isa : kSimdIsas) {
    RenderOptions asked, best;
    asked.backend = best.backend = Backend::simd;
    asked.isa = isa;
    best.isa = capped_isa(isa);
    INFO("isa ", std::string(isa_name(isa)), " runs as ", std::string(isa_name(*best.isa)));
    CHECK(resolved_isa(asked) == *best.isa);
    Buffer a(5, 4, 15), b(5, 4, 15);
    REQUIRE(render(small_scene(), asked, a.view).ok());
    REQUIRE(render(small_scene(), best, b.view).ok());
    CHECK(a.pixels == b.pixels);
  }
}

TEST_CASE("a million threads are capped and render the same bytes as one thread, for every backend" * par2d::test::per_isa()) {
  for (Backend backend : {Backend::scalar, Backend::simd, Backend::raycast}) {
    RenderOptions one;
    one.backend = backend;
    one.threads = 1;
    one.rays = 32;
    RenderOptions many = one;
    many.threads = 1000000;
    Status s1, s2;
    const test::RenderedImage a = test::render_image(small_scene(), one, s1);
    const test::RenderedImage b = test::render_image(small_scene(), many, s2);
    INFO(backend_name(backend));
    REQUIRE(s1.ok());
    REQUIRE_MESSAGE(s2.ok(), s2.message());
    CHECK(a.pixels == b.pixels);
  }
}

TEST_CASE("rays are ignored by the non-raycast backends") {
  RenderOptions o;
  o.backend = Backend::scalar;
  o.rays = 0;
  Buffer b(5, 4, 15);
  CHECK(render(small_scene(), o, b.view).ok());
}

// FINDINGS.md #1: an isa value below the enum once reached the kernel table and crashed;
// check_options (src/render/render_arguments.cpp) refuses both ends.
TEST_CASE("an isa below the enum is invalid_argument") {
  RenderOptions o;
  o.backend = Backend::simd;
  o.isa = static_cast<Isa>(-1);
  Buffer b(5, 4, 15);
  const Status s = render(small_scene(), o, b.view);
  CHECK(s.code() == StatusCode::invalid_argument);
  CHECK(mentions(s, "isa"));
}

// FINDINGS.md #2: a backend value outside the enum renders as SIMD instead of being refused.
TEST_CASE("a backend beyond the enum is invalid_argument") {
  RenderOptions o;
  o.backend = static_cast<Backend>(9);
  Buffer b(5, 4, 15);
  const Status s = render(small_scene(), o, b.view);
  CHECK(s.code() == StatusCode::invalid_argument);
  CHECK(mentions(s, "backend"));
}
