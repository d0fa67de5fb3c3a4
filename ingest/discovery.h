#pragma once
// Finding the tests in the paths given to `napkin import` (and `napkin
// transform`, `napkin serve`'s inbox): every format of the input-format
// table (ingest/input_formats.h), file groups grouped by folder and stem.
#include <string>
#include <vector>

#include "ingest/input_formats.h"

namespace napkin::ingest {

struct Discovery {
  std::vector<ImportInput> inputs;  // in path order; tests inside a folder sorted by name
  std::vector<std::string> errors;  // one sentence per path that holds no test
};

// Finds the tests in `paths`:
// - a file some format names (InputFormatEntry::names_test; formats sharing
//   a name told apart by the file's first bytes): one test of that format;
//   a kFolder format's file stands for its folder (an .mme file: the ISO-MME
//   test folder around it); a kFileGroup format's files are grouped with
//   the other given files of their folder and stem;
// - a folder that is a test of a kFolder format (holding an .mme file): one test;
// - any other folder: every test inside it, searched recursively (other files are ignored).
// A path that does not exist, an unrecognised file or a folder without any
// test is reported in `errors`, and so is a file napkin would read that is
// no regular file (a FIFO, a device: never opened).
Discovery DiscoverInputs(const std::vector<std::string>& paths);

}  // namespace napkin::ingest
