// swum-emu: the virtual two-phase ultrasonic-motor amplifier with its motor attached.
// docs/emulator.md (usage), docs/protocols.md (interfaces). The options: emu_options.h; the
// wiring, the run and the exit report: emu_app.h. Here only failures become exit statuses.
#include <cstdio>
#include <exception>

#include "app/emu_app.h"
#include "app/emu_options.h"

int main(int argc, char** argv) {
  using namespace swum::emu;
  try {
    return run_emulator(parse_emu_options(argc, argv));
  } catch (const EmuCliExit& e) {  // --help, or a usage error in CLI11's words
    std::fputs(e.out().c_str(), stdout);
    std::fputs(e.err().c_str(), stderr);
    return e.exit_code();
  } catch (const std::exception& e) {  // a bad option value, or a start-up failure: one line
    std::fprintf(stderr, "swum-emu: %s\n", e.what());
    return 1;
  }
}
