// doctest entry point for the whole suite, with the listener that keeps the test tiers
// honest (tests/support/test_tiers.hpp): whether a case depends on PAR2D_ISA is measured, not
// remembered, so a new case that renders with the automatic backend cannot be left out of
// the per-ISA runs.
#define DOCTEST_CONFIG_IMPLEMENT
#include <doctest/doctest.h>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "render/isa_usage.hpp"
#include "support/test_tiers.hpp"

namespace {

std::vector<std::string>& tier_violations() {
  static std::vector<std::string> violations;
  return violations;
}

unsigned& cases_selected() {
  static unsigned count = 0;
  return count;
}

struct TierListener : doctest::IReporter {
  explicit TierListener(const doctest::ContextOptions&) {}

  void test_case_start(const doctest::TestCaseData& data) override {
    current_ = &data;
    queries_at_start_ = par2d::detail::default_isa_queries();
  }
  void test_case_end(const doctest::CurrentTestCaseStats& stats) override {
    // A failed case may have stopped before its render: its failure is the report.
    if (!current_ || !stats.testCaseSuccess) return;
    const bool uses_default_isa = par2d::detail::default_isa_queries() != queries_at_start_;
    const char* suite = current_->m_test_suite ? current_->m_test_suite : "";
    const bool tagged = std::strcmp(suite, par2d::test::kPerIsaSuite) == 0;
    const bool long_tier = std::strcmp(suite, par2d::test::kLongSuite) == 0;
    std::string where = std::string(current_->m_file.c_str()) + ":" + std::to_string(current_->m_line) +
                        ": test case \"" + current_->m_name + "\" ";
    if (uses_default_isa && !tagged && !long_tier)
      tier_violations().push_back(where + "renders with the default ISA but is not in the per_isa suite; add "
                                          "`* par2d::test::per_isa()` so every level runs it");
    else if (!uses_default_isa && tagged)
      tier_violations().push_back(where + "is in the per_isa suite but never resolves the default ISA; the "
                                          "per-ISA runs would repeat it for nothing: drop the tag");
  }

  void report_query(const doctest::QueryData&) override {}
  void test_run_start() override {}
  void test_run_end(const doctest::TestRunStats& stats) override { cases_selected() = stats.numTestCasesPassingFilters; }
  void test_case_reenter(const doctest::TestCaseData&) override {}
  void test_case_exception(const doctest::TestCaseException&) override {}
  void subcase_start(const doctest::SubcaseSignature&) override {}
  void subcase_end() override {}
  void log_assert(const doctest::AssertData&) override {}
  void log_message(const doctest::MessageData&) override {}
  void test_case_skipped(const doctest::TestCaseData&) override {}

 private:
  const doctest::TestCaseData* current_ = nullptr;
  std::uint64_t queries_at_start_ = 0;
};

REGISTER_LISTENER("test_tiers", 1, TierListener);

}  // namespace

int main(int argc, char** argv) {
  doctest::Context context(argc, argv);
  const int status = context.run();
  if (context.shouldExit()) return status;
  // A filter that selects nothing (a ctest entry whose file lost its cases, a mistyped suite)
  // is a failure, not a pass.
  if (cases_selected() == 0) {
    std::fprintf(stderr, "par2d_tests: no test case passes the filters\n");
    return status != 0 ? status : 1;
  }
  for (const std::string& violation : tier_violations()) std::fprintf(stderr, "%s\n", violation.c_str());
  if (!tier_violations().empty()) {
    std::fprintf(stderr, "test tiers: %zu case(s) in the wrong tier (tests/support/test_tiers.hpp)\n",
                 tier_violations().size());
    return status != 0 ? status : 1;
  }
  return status;
}
