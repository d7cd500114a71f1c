// The one Catch2 main shared by every test executable, with the listener that turns IGI_SKIP
// into CTest's "skipped" (see scenes.hpp).
#define CATCH_CONFIG_MAIN
#include <catch2/catch.hpp>

#include <iostream>

#include "scenes.hpp"

namespace {

/// Prints scenes.hpp's skip marker at the end of a test case that called IGI_SKIP, unless an
/// assertion of that case failed: then it says so instead, and the case stays a failure.
struct SkipListener : Catch::TestEventListenerBase {
  using TestEventListenerBase::TestEventListenerBase;

  void testCaseStarting(const Catch::TestCaseInfo& info) override {
    TestEventListenerBase::testCaseStarting(info);
    igi::testing::skip_reason().clear();
  }

  void testCaseEnded(const Catch::TestCaseStats& stats) override {
    std::string& reason = igi::testing::skip_reason();
    if (!reason.empty()) {
      if (stats.totals.assertions.failed == 0)
        std::cout << igi::testing::skip_marker << stats.testInfo.name << ": " << reason << std::endl;
      else
        std::cout << "not skipped, failed: " << stats.testInfo.name << " asked to skip (" << reason
                  << ") after a failed assertion" << std::endl;
      reason.clear();
    }
    TestEventListenerBase::testCaseEnded(stats);
  }
};

}  // namespace

CATCH_REGISTER_LISTENER(SkipListener)
