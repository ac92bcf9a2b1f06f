#include "ensembles/program/interrupt.hpp"

#include <signal.h>
#include <unistd.h>

#include <csignal>
#include <cstdlib>
#include <mutex>
#include <string>

#include "core/error.hpp"

namespace qmaps {
namespace {

volatile std::sig_atomic_t received = 0;
volatile std::sig_atomic_t from_parent = 0;  // the first signal was sent by this process's parent

// The first signal asks the run to stop; a second one, of any of the three, ends the process
// at once with that signal's default action.
extern "C" void on_signal(int sig, siginfo_t* info, void*) {
  if (received == 0) {
    from_parent = info != nullptr && info->si_code == SI_USER && info->si_pid == getppid();
    received = sig;
    return;
  }
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

// SIGHUP (a dropped terminal or ssh session) stops the run as SIGTERM does.
constexpr int signals[3] = {SIGINT, SIGTERM, SIGHUP};
struct sigaction previous[3];

// Guards alive at once (runs in several threads of one process, nested calls): the first
// installs the handlers, the last restores what was there before the first.
std::mutex guarding;
int guards = 0;

}  // namespace

InterruptGuard::InterruptGuard() {
  const std::lock_guard lock(guarding);
  if (guards++ > 0) return;
  received = 0;
  from_parent = 0;
  struct sigaction action {};
  action.sa_sigaction = on_signal;
  action.sa_flags = SA_SIGINFO;
  sigemptyset(&action.sa_mask);
  for (int k = 0; k < 3; ++k) sigaction(signals[k], &action, &previous[k]);
}

InterruptGuard::~InterruptGuard() {
  const std::lock_guard lock(guarding);
  if (--guards > 0) return;
  for (int k = 0; k < 3; ++k) sigaction(signals[k], &previous[k], nullptr);
}

bool InterruptGuard::requested() const { return received != 0; }
int InterruptGuard::signal() const { return received; }

std::string InterruptGuard::named(int sig) const {
  const bool from_mpirun = sig == SIGTERM && received == SIGTERM && from_parent != 0 &&
                           std::getenv("OMPI_COMM_WORLD_SIZE") != nullptr;
  return from_mpirun ? "SIGTERM from mpirun (which sends it for a SIGINT or a SIGTERM)"
                     : signal_name(sig);
}

const char* signal_name(int sig) {
  return sig == SIGINT ? "SIGINT" : sig == SIGTERM ? "SIGTERM" : sig == SIGHUP ? "SIGHUP" : "a signal";
}

Interrupted::Interrupted(int sig, const std::string& doing, const std::string& outcome)
    : Error(ExitCode::interrupted,
            std::string(signal_name(sig)) + " while " + doing + ": " + outcome),
      signal_(sig) {}

void stop_if_interrupted(const char* doing, const char* outcome) {
  if (received != 0) [[unlikely]]
    throw Interrupted(received, doing, outcome);
}

SelfSignal SelfSignal::from_environment() {
  SelfSignal s;
  const char* value = std::getenv("QMAPS_SIGNAL_AT_STEP");
  if (!value || !*value) return s;
  const std::string text(value);
  const auto colon = text.find(':');
  const std::string name = colon == std::string::npos ? "" : text.substr(colon + 1);
  s.signal_ = name == "INT"    ? SIGINT
              : name == "TERM" ? SIGTERM
              : name == "HUP"  ? SIGHUP
              : name == "KILL" ? SIGKILL
                               : 0;
  std::size_t used = 0;
  try {
    s.step_ = std::stoll(text.substr(0, colon), &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (s.signal_ == 0 || used != colon || s.step_ < 1)
    throw usage_error("QMAPS_SIGNAL_AT_STEP='" + text +
                      "': expected STEP:INT, STEP:TERM, STEP:HUP or STEP:KILL with STEP >= 1");
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
