// The command line's pictures: maps of run directories drawn by scripts/plot_maps.py
// (matplotlib, started by argument vector) and gfmd plot DIR.
#pragma once

#include <string>
#include <vector>

#include "gfmd/case/outputs.hpp"

namespace gfmd::cli {

// Draws the PNG maps of run directories with plot_maps.py (matplotlib) from their fields.nc,
// or from the staging file write_outputs leaves when output.fields is off (removed here,
// drawn or not). `options` go before the directories (e.g. --profiles, --only current).
// Never throws: a failure is a warning (the data files are complete); returns false then.
bool draw_maps(const std::vector<std::string>& dirs, const std::vector<std::string>& options);

// The run directories below dir whose maps are still to be drawn (case/outputs.hpp).
using gfmd::runs_needing_maps;

// gfmd plot DIR: redraws the figures of a run directory (maps from fields.nc, profiles.png
// from profiles.csv), of a sweep (its sweep_<y>.png plots, the default one if none, and the
// maps of its points), of an ensemble (its seeds' maps) or of a study (the maps and plots of
// its series; the study figure itself is drawn by gfmd study, which reuses every result).
int cmd_plot(const std::string& dir);

}  // namespace gfmd::cli
