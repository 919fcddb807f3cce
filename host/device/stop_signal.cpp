#include "device/stop_signal.h"

#include <csignal>

namespace swum::host {
namespace {
volatile std::sig_atomic_t g_stop = 0;
struct sigaction g_previous_int {};
struct sigaction g_previous_term {};
void on_signal(int) { g_stop = 1; }
}  // namespace

StopSignal::StopSignal() {
  struct sigaction action {};
  action.sa_handler = on_signal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = 0;  // no SA_RESTART: interrupt blocking calls
  sigaction(SIGINT, &action, &g_previous_int);
  sigaction(SIGTERM, &action, &g_previous_term);
}

StopSignal::~StopSignal() {
  sigaction(SIGINT, &g_previous_int, nullptr);
  sigaction(SIGTERM, &g_previous_term, nullptr);
}

bool StopSignal::requested() { return g_stop != 0; }
void StopSignal::reset_for_tests() { g_stop = 0; }

}  // namespace swum::host
