#include "postproc/analysis.hpp"

namespace nvh::postproc {

// Each analysis's file defines its factory; declared here only, so that no header lists them all.
std::unique_ptr<Analysis> make_spectrum_analysis();
std::unique_ptr<Analysis> make_octave_analysis();
std::unique_ptr<Analysis> make_orders_analysis();
std::unique_ptr<Analysis> make_stats_analysis();
std::unique_ptr<Analysis> make_erp_analysis();
std::unique_ptr<Analysis> make_animate_analysis();
std::unique_ptr<Analysis> make_history_analysis();
std::unique_ptr<Analysis> make_impacts_analysis();

const std::vector<AnalysisEntry>& analyses() {
  // The registry: one line per analysis (subcommand, `postproc --help` line, factory).
  static const std::vector<AnalysisEntry> registry = {
      {"spectrum", "Welch spectra: amplitude, RMS or PSD, with dB levels", make_spectrum_analysis},
      {"octave", "fractional-octave band levels (IEC 61260-1), A-weighting, Leq", make_octave_analysis},
      {"orders", "computed order tracking: order spectra per cycle, cuts, Campbell", make_orders_analysis},
      {"stats", "RMS, peak, crest factor, band RMS, harmonics of the running speed", make_stats_analysis},
      {"erp", "surface normal velocity and equivalent radiated power of a flexible body", make_erp_analysis},
      {"animate", "a flexible body's deformed surface over time as XDMF + HDF5 for ParaView",
       make_animate_analysis},
      {"history", "a signal's samples in its time or crank-angle window, with time and angle",
       make_history_analysis},
      {"impacts", "the impacts of a contact force: instants, velocity and energy of the impacting body",
       make_impacts_analysis},
  };
  return registry;
}

}  // namespace nvh::postproc
