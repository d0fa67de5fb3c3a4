#include "cli/catalogue_access.h"

namespace napkin::cli {

db::Catalogue OpenCatalogue(const GlobalOptions& global, bool read_only) {
  db::CatalogueOptions options;
  options.read_only = read_only;
  return db::Catalogue::Open(global.db_path, options);
}

}  // namespace napkin::cli
