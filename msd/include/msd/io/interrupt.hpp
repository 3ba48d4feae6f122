// Stopping cleanly on SIGINT/SIGTERM. Commands that write results install the
// handler. Inside an InterruptibleSection (a time loop that polls
// interrupt_signal() every step) a signal only sets a flag: the loop stops at
// its next step, marks its results failed ("interrupted by signal N at t = ...")
// and the program exits with interrupted_exit_code(N). Anywhere else (meshing,
// writing a VTU), and on a second signal, the handler removes every registered
// temporary file and ends the process at once with the same code.
#pragma once

#include "msd/integrate/step.hpp"

#include <signal.h>

#include <string>

namespace msd {

/// Installs the SIGINT/SIGTERM handler (idempotent).
void install_interrupt_handlers();

/// The signal received inside an InterruptibleSection, 0 when none.
int interrupt_signal();

/// 128 + signal: 130 for SIGINT, 143 for SIGTERM (the shell's convention).
inline int interrupted_exit_code(int signal) { return 128 + signal; }

/// "interrupted by signal 2 (SIGINT)".
std::string interrupt_description(int signal);

/// A run stopped by a signal: "interrupted by signal 2 (SIGINT) at t = ... s (step ...)".
class Interrupted : public SimulationFailure {
 public:
  Interrupted(int sig, double at_time, long at_step)
      : SimulationFailure(interrupt_description(sig), at_time, at_step, -1, -1), signal(sig) {}
  int signal;
};

/// Throws Interrupted when a signal arrived inside an InterruptibleSection.
inline void throw_if_interrupted(double at_time, long at_step) {
  if (const int sig = interrupt_signal()) throw Interrupted(sig, at_time, at_step);
}

/// SIGINT and SIGTERM held back (pending, delivered when it ends) while one
/// exists: for changes the handler must never see half done.
class SignalsBlocked {
 public:
  SignalsBlocked();
  ~SignalsBlocked();
  SignalsBlocked(const SignalsBlocked&) = delete;
  SignalsBlocked& operator=(const SignalsBlocked&) = delete;

 private:
  sigset_t old_;
};

/// While one exists a signal sets the flag instead of ending the process.
class InterruptibleSection {
 public:
  InterruptibleSection();
  ~InterruptibleSection();
  InterruptibleSection(const InterruptibleSection&) = delete;
  InterruptibleSection& operator=(const InterruptibleSection&) = delete;
};

/// A temporary file the handler removes when it ends the process. Registered
/// for the object's lifetime (at most 64 at a time; more are not registered).
class RegisteredTemporary {
 public:
  explicit RegisteredTemporary(const std::string& path);
  ~RegisteredTemporary();
  RegisteredTemporary(const RegisteredTemporary&) = delete;
  RegisteredTemporary& operator=(const RegisteredTemporary&) = delete;

 private:
  int slot_ = -1;
};

}  // namespace msd
