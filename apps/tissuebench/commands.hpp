// The subcommands of the tissuebench program. Each returns the process exit
// code: 0 success, 1 a run that failed (blow-up, non-finite value), 2 bad input.
#pragma once

#include <string>
#include <vector>

namespace app {

struct RunArgs {
  std::string spec, out, solver = "msd";
  bool quiet = false;
};
int cmd_run(const RunArgs& args);

struct SuiteArgs {
  std::string out = "results";
  std::string specs_dir;
  bool quiet = false;
};
int cmd_suite(const SuiteArgs& args);

struct InspectArgs {
  std::string spec;
};
int cmd_inspect(const InspectArgs& args);

struct ConvergeArgs {
  std::string spec, out = "convergence";
  std::vector<int> levels{0, 1, 2};
  unsigned degree = 0;  ///< 0: the spec's
  bool quiet = false;
};
int cmd_converge(const ConvergeArgs& args);

struct CompareArgs {
  std::string msd, fem, json;
};
int cmd_compare(const CompareArgs& args);

/// The specs of the default suite (the thesis' three uni-axial experiments).
std::vector<std::string> default_suite();

}  // namespace app
