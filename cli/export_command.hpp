#pragma once
// `demcal export <study.toml> --to liggghts|lammps|edem-csv|json`: the
// calibrated material card (study/material_export.hpp); argument parsing only.
#include "study/material_export.hpp"

#include <CLI/CLI.hpp>

#include <ostream>

namespace demcal::cli {

struct ExportOptions {
  study::MaterialExportOptions card;
  std::string card_file;  // --card; empty: the default place
};

CLI::App* add_export_command(CLI::App& app, ExportOptions& options);
// Writes the card; prints its path to `out` and each warning to `log`. Returns 0.
int run_export(ExportOptions& options, std::ostream& out, std::ostream& log);

}  // namespace demcal::cli
