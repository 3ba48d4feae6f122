// Scripted muscle activation (thesis 5.7): open-loop control by a text script
// of commands, one per line,
//
//     <time> <muscle name> <activation value> <time scale>
//
// ("at `time`, move `muscle`'s activation linearly to `value` over `time
// scale` seconds"); `%` starts a comment; blank lines are ignored. A command
// starts from the activation in effect at its time, so a command that arrives
// during a ramp interrupts it. Before its first command a muscle's activation
// is 0. Example (the thesis' hamstrings script, msd/data/scripts/):
//
//     % Increase back muscle activation gradually
//     0.01 BACK_MUSCLE 0.4 0.99
#pragma once

#include <set>
#include <string>
#include <vector>

namespace msd {

struct ActivationCommand {
  double time = 0.0;       ///< s
  std::string muscle;      ///< as written
  double activation = 0.0; ///< target, 0..1
  double timescale = 0.0;  ///< s; 0 = a step
  int line = 0;            ///< in the source, for messages
};

struct ActivationScript {
  std::string source;
  std::vector<ActivationCommand> commands;  ///< in file order (times never decrease)

  /// Activation of `muscle` at time t (0 before its first command, and for a
  /// muscle the script never names). Names compare case-insensitively.
  double activation(const std::string& muscle, double t) const;
  /// The muscles the script names, upper-cased, sorted.
  std::vector<std::string> muscles() const;
};

/// Parses a script. Errors (msd::Error) read "SOURCE:LINE: what": a line
/// without four fields, a field that is not a number, a negative time or time
/// scale, a time earlier than the line before, an activation outside [0, 1],
/// or - when `known_muscles` is not empty - a muscle not in it (compared
/// case-insensitively; the message lists the known ones).
ActivationScript parse_activation_script(const std::string& text, const std::string& source,
                                         const std::set<std::string>& known_muscles = {});

/// Reads and parses a script file.
ActivationScript read_activation_script(const std::string& path, const std::set<std::string>& known_muscles = {});

}  // namespace msd
