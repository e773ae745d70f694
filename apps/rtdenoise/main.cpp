// rtdenoise — command-line front end. Every subcommand is a client of the public API.
#include <cstdio>

#include "cli.h"

int main(int argc, char** argv) {
  CLI::App app{"rtdenoise: real-time denoisers for 1-spp path-traced sequences"};
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
#endif
  rtd::cli::addDevices(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const rtd::Error& e) {
    std::fprintf(stderr, "rtdenoise: error: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rtdenoise: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
