// rtdenoise — command-line front end. Every subcommand is a client of the public API; the
// conventions they share (exit codes, option spellings) are in cli.h and docs/cli.md.
#include <cstdio>
#include <filesystem>
#include <new>
#include <string>

#include "cli.h"
#include "interrupt.h"

int main(int argc, char** argv) {
  using namespace rtd::cli;
  installInterruptHandlers();
  CLI::App app{"rtdenoise: real-time denoisers for 1-spp path-traced sequences", "rtdenoise"};
  app.set_version_flag("--version", std::string("rtdenoise ") + rtd::versionString());
  app.footer(kExitStatusFooter);
  app.require_subcommand(1);
  addDenoise(app);
  addMethods(app);
  addBench(app);
#ifdef HAVE_RTDENOISE_EVAL
  addEval(app);
  addCompare(app);
  addDemo(app);
#endif
#ifdef HAVE_RTDENOISE_RENDER
  addRender(app);
  addDataset(app);
#endif
  addPack(app);
  addDevices(app);

  // An unknown subcommand is named (CLI11 alone would say "arguments were not expected").
  if (argc > 1 && argv[1][0] != '-') {
    bool known = false;
    std::string names;
    for (const CLI::App* sub : app.get_subcommands({})) {
      known |= sub->get_name() == argv[1];
      names += (names.empty() ? "" : ", ") + sub->get_name();
    }
    if (!known) {
      std::fprintf(stderr, "rtdenoise: unknown subcommand '%s' (subcommands: %s; see rtdenoise --help)\n", argv[1],
                   names.c_str());
      return kExitUsage;
    }
  }
  const std::string which = argc > 1 && argv[1][0] != '-' ? std::string(" ") + argv[1] : std::string();
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int printed = app.exit(e);  // prints help/version (0) or the parse error
    return printed == 0 ? kExitOk : kExitUsage;
  } catch (const UsageError& e) {
    std::fprintf(stderr, "rtdenoise%s: usage error: %s (see rtdenoise%s --help)\n", which.c_str(), e.what(), which.c_str());
    return kExitUsage;
  } catch (const rtd::Error& e) {
    std::fprintf(stderr, "rtdenoise%s: error: %s\n", which.c_str(), e.what());
    return kExitBadInput;
  } catch (const std::filesystem::filesystem_error& e) {  // the user's paths: a missing or unwritable directory
    std::fprintf(stderr, "rtdenoise%s: error: %s\n", which.c_str(), e.what());
    return kExitBadInput;
  } catch (const std::bad_alloc&) {  // inputs too large for this machine (the library refuses absurd sizes)
    std::fprintf(stderr, "rtdenoise%s: error: out of memory\n", which.c_str());
    return kExitBadInput;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rtdenoise%s: internal error: %s\n", which.c_str(), e.what());
    return kExitInternal;
  }
  return kExitOk;
}
