#include "ensembles/program/interrupt.hpp"

#include <csignal>
#include <cstdlib>
#include <string>

#include "core/error.hpp"

namespace qmaps {
namespace {

volatile std::sig_atomic_t received = 0;

extern "C" void on_signal(int sig) { received = sig; }

constexpr int signals[2] = {SIGINT, SIGTERM};
struct sigaction previous[2];

}  // namespace

InterruptGuard::InterruptGuard() {
  received = 0;
  struct sigaction action {};
  action.sa_handler = on_signal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESETHAND;  // the second signal takes its default action: the end
  for (int k = 0; k < 2; ++k) sigaction(signals[k], &action, &previous[k]);
}

InterruptGuard::~InterruptGuard() {
  for (int k = 0; k < 2; ++k) sigaction(signals[k], &previous[k], nullptr);
}

bool InterruptGuard::requested() const { return received != 0; }
int InterruptGuard::signal() const { return received; }

SelfSignal SelfSignal::from_environment() {
  SelfSignal s;
  const char* value = std::getenv("QMAPS_SIGNAL_AT_STEP");
  if (!value || !*value) return s;
  const std::string text(value);
  const auto colon = text.find(':');
  const std::string name = colon == std::string::npos ? "" : text.substr(colon + 1);
  s.signal_ = name == "INT" ? SIGINT : name == "TERM" ? SIGTERM : name == "KILL" ? SIGKILL : 0;
  std::size_t used = 0;
  try {
    s.step_ = std::stoll(text.substr(0, colon), &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (s.signal_ == 0 || used != colon || s.step_ < 1)
    throw usage_error("QMAPS_SIGNAL_AT_STEP='" + text +
                      "': expected STEP:INT, STEP:TERM or STEP:KILL with STEP >= 1");
  return s;
}

long long SelfSignal::segment_end(long long first, long long last) const {
  return step_ > first && step_ < last ? step_ : last;
}

void SelfSignal::deliver_if_due(long long step) {
  if (step_ < 0 || step < step_) return;
  step_ = -1;
  std::raise(signal_);
}

}  // namespace qmaps
