#include "interrupt.h"

#include <signal.h>

#include "rtd/sequence.h"

namespace rtd::cli {

namespace {

extern "C" void onInterrupt(int sig) {
  rtd::removeTemporaryFiles();  // async-signal-safe
  // End as the signal would have: the parent sees "killed by SIGINT", not a normal exit.
  ::signal(sig, SIG_DFL);
  ::raise(sig);
}

}  // namespace

void installInterruptHandlers() {
  struct sigaction sa {};
  sa.sa_handler = onInterrupt;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = 0;
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) ::sigaction(sig, &sa, nullptr);
}

}  // namespace rtd::cli
