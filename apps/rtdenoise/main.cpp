// rtdenoise — command-line front end. Every subcommand is a client of the public API.
#include <cstdio>
#include <string>

#include "cli.h"

int main(int argc, char** argv) {
  CLI::App app{"rtdenoise: real-time denoisers for 1-spp path-traced sequences"};
  app.set_version_flag("--version", std::string("rtdenoise ") + rtd::versionString());
  app.footer("Exit status: 0 success, 1 bad input, 2 usage error, 3 internal error.");
  app.require_subcommand(1);
  rtd::cli::addDenoise(app);
  rtd::cli::addMethods(app);
  rtd::cli::addBench(app);
#ifdef HAVE_RTDENOISE_EVAL
  rtd::cli::addEval(app);
  rtd::cli::addCompare(app);
  rtd::cli::addDemo(app);
#endif
#ifdef HAVE_RTDENOISE_RENDER
  rtd::cli::addRender(app);
  rtd::cli::addDataset(app);
#endif
  rtd::cli::addDevices(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int printed = app.exit(e);  // prints help/version (0) or the parse error
    return printed == 0 ? rtd::cli::kExitOk : rtd::cli::kExitUsage;
  } catch (const rtd::Error& e) {
    std::fprintf(stderr, "rtdenoise: error: %s\n", e.what());
    return rtd::cli::kExitBadInput;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rtdenoise: internal error: %s\n", e.what());
    return rtd::cli::kExitInternal;
  }
  return rtd::cli::kExitOk;
}
