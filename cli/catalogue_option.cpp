#include "cli/catalogue_option.h"

namespace napkin::cli {

db::Catalogue OpenCatalogue(const GlobalOptions& global, bool read_only) {
  db::CatalogueOptions options;
  options.read_only = read_only;
  // Never write into a damaged catalogue (init, import, synth, run, merge).
  options.check_integrity = !read_only;
  return db::Catalogue::Open(global.db_path, options);
}

}  // namespace napkin::cli
