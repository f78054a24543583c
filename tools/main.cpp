// acuity — perceptual level-of-detail tools. `acuity --help` lists the subcommands.
#include <cstdio>
#include <exception>

#include "acuity/lodgen/versions.hpp"
#include "acuity/spectra/versions.hpp"
#include "acuity/version.hpp"
#include "commands.hpp"

int main(int argc, char** argv) {
  CLI::App app{"acuity: draw only the geometric detail a viewer can see"};
  app.require_subcommand(0, 1);
  app.add_flag_callback(
      "--version",
      [] {
        std::printf("acuity %s\n  lodgen:  %s\n  spectra: %s\n", ACUITY_VERSION_STRING,
                    acuity::lodgen::library_versions().c_str(), acuity::spectra::library_versions().c_str());
        throw CLI::Success();
      },
      "Print the version and the libraries it was built with");
  acuity::tools::add_models_report(app);
  acuity::tools::add_profile_command(app);
  acuity::tools::add_inspect_command(app);
  acuity::tools::add_lodgen_command(app);
  acuity::tools::add_simulate_commands(app);
  acuity::tools::add_plan_command(app);
  acuity::tools::add_demo_command(app, argc > 0 ? argv[0] : "acuity");
  acuity::tools::add_bake_command(app);
  try {
    app.parse(argc, argv);
    if (app.get_subcommands().empty()) {
      std::fputs(app.help().c_str(), stdout);
      return 0;
    }
  } catch (const CLI::ParseError& e) { return app.exit(e); } catch (const std::exception& e) {
    std::fprintf(stderr, "acuity: %s\n", e.what());
    return 1;
  }
  return 0;
}
