// Shared by the accuracy tests (issue 17, item 5): a shipped spec as one of
// the suite's MSD variants, and a run of both solvers on it compared.
#pragma once

#include "bench/compare.hpp"
#include "bench/fem_runner.hpp"
#include "bench/msd_runner.hpp"
#include "bench/spec.hpp"
#include "bench/suite.hpp"

#include "test_support.hpp"

#include <gtest/gtest.h>

#include <iostream>
#include <string>

namespace accuracy_support {

/// The shipped spec `name`, its text edited first (the first `find` replaced
/// by `replace`, when given), as the suite's variant `variant`.
inline bench::Spec variant_spec(const std::string& name, const std::string& variant, const std::string& find = "",
                                const std::string& replace = "") {
  bench::Spec spec = bench::load_spec(std::string(TISSUEBENCH_SPECS_DIR) + "/" + name);
  if (!find.empty()) {
    std::string text = spec.text;
    const size_t at = text.find(find);
    if (at == std::string::npos) throw msd::Error(name + ": the test's edit does not find '" + find + "'");
    text.replace(at, find.size(), replace);
    spec = bench::parse_spec(text, spec.path);
  }
  return bench::suite_variant(spec, variant, TISSUEBENCH_CALIBRATION_DIR);
}

/// Both solvers on `spec` (files in `dir`), the MSD compared with the FEM.
inline bench::Comparison run_both(const bench::Spec& spec, const testing_support::TempDir& dir) {
  const std::string fem = dir.file(spec.name + "_fem.h5"), msd = dir.file(spec.name + "_msd.h5");
  const bench::RunSummary f = bench::run_fem(spec, fem);
  EXPECT_TRUE(f.complete) << f.failure;
  const bench::RunSummary m = bench::run_msd(spec, msd);
  EXPECT_TRUE(m.complete) << m.failure;
  const bench::Comparison c = bench::compare_results(msd, fem);
  // The figures, for the log: what the assertions saw.
  std::cout << spec.name << ": load curve " << 100 * c.load_rel_rms << " %, volume ratio error " << c.volume_ratio_max_error
            << ", frequency error " << 100 * c.frequency_rel_error << " %\n";
  return c;
}

}  // namespace accuracy_support
