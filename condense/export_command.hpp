#pragma once
// `condense export`: a superelement file written for another program (Nastran DMIG bulk data), a thin
// command line over condense/matrix_export.hpp. main.cpp hands it the arguments after "condense".
namespace nvh::condense {

/// Run `condense export ...`: argv[0] is "export", the rest its options. Returns the exit code
/// (0 success, 1 bad input or failed write, 2 bad command line).
int run_export_command(int argc, char** argv);

}  // namespace nvh::condense
