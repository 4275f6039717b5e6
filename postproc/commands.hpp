#pragma once
// The postproc subcommands as library functions (one file each under postproc/analyses/; the extension
// point is postproc/analysis.hpp). This header gathers them for callers that use several.
#include "postproc/analyses/octave.hpp"
#include "postproc/analyses/orders.hpp"
#include "postproc/analyses/spectrum.hpp"
#include "postproc/analyses/stats.hpp"
#include "postproc/options.hpp"
