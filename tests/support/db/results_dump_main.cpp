// napkin_results_dump CATALOGUE: prints db::CanonicalResultsDump (results_dump.h)
// so shell tests compare two catalogues with cmp.
#include <cstdio>
#include <exception>

#include "tests/support/db/results_dump.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: napkin_results_dump CATALOGUE\n");
    return 2;
  }
  try {
    const std::string dump = napkin::db::CanonicalResultsDump(argv[1]);
    std::fwrite(dump.data(), 1, dump.size(), stdout);
    return 0;
  } catch (const std::exception& error) {
    std::fprintf(stderr, "napkin_results_dump: %s\n", error.what());
    return 1;
  }
}
