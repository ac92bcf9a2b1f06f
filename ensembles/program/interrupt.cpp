#include "ensembles/program/interrupt.hpp"

#include <csignal>

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

}  // namespace qmaps
