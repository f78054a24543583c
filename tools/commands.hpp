#pragma once
// Subcommands of the acuity command. Each add_* registers its options and callback on the app.
#include <CLI/CLI.hpp>

namespace acuity::tools {
void add_models_report(CLI::App& app);  // `acuity models`, and `acuity demo` until the demo scene exists
}  // namespace acuity::tools
