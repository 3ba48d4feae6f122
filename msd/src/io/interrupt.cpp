#include "msd/io/interrupt.hpp"

#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cstring>

namespace msd {

namespace {

constexpr int kSlots = 64;
constexpr size_t kPathMax = 4096;
char g_paths[kSlots][kPathMax];
std::atomic<int> g_used[kSlots];
std::atomic<int> g_depth{0};
volatile sig_atomic_t g_signal = 0;

void remove_temporaries() {
  for (int i = 0; i < kSlots; ++i)
    if (g_used[i].load() == 1) unlink(g_paths[i]);
}

extern "C" void on_signal(int sig) {
  if (g_depth.load() > 0 && g_signal == 0) {
    g_signal = sig;  // the loop stops at its next step
    return;
  }
  remove_temporaries();
  _exit(interrupted_exit_code(sig));
}


}  // namespace

SignalsBlocked::SignalsBlocked() {
  sigset_t s;
  sigemptyset(&s);
  sigaddset(&s, SIGINT);
  sigaddset(&s, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &s, &old_);
}

SignalsBlocked::~SignalsBlocked() { pthread_sigmask(SIG_SETMASK, &old_, nullptr); }

void install_interrupt_handlers() {
  struct sigaction sa;
  std::memset(&sa, 0, sizeof sa);
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sigaddset(&sa.sa_mask, SIGINT);
  sigaddset(&sa.sa_mask, SIGTERM);
  sa.sa_flags = SA_RESTART;
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  // A full disk or a file size limit is a write error to report, not a kill.
  signal(SIGXFSZ, SIG_IGN);
}

int interrupt_signal() { return static_cast<int>(g_signal); }

std::string interrupt_description(int sig) {
  const char* name = sig == SIGINT ? "SIGINT" : sig == SIGTERM ? "SIGTERM" : "signal";
  return "interrupted by signal " + std::to_string(sig) + " (" + name + ")";
}

InterruptibleSection::InterruptibleSection() { ++g_depth; }
InterruptibleSection::~InterruptibleSection() { --g_depth; }

RegisteredTemporary::RegisteredTemporary(const std::string& path) {
  if (path.size() >= kPathMax) return;
  const SignalsBlocked b;  // the handler never sees a half-written slot
  for (int i = 0; i < kSlots; ++i)
    if (g_used[i].load() == 0) {
      std::memcpy(g_paths[i], path.c_str(), path.size() + 1);
      g_used[i].store(1);
      slot_ = i;
      return;
    }
}

RegisteredTemporary::~RegisteredTemporary() {
  if (slot_ < 0) return;
  const SignalsBlocked b;  // the handler never sees a half-written slot
  g_used[slot_].store(0);
}

}  // namespace msd
