#pragma once
// A private temporary folder (mkdtemp under $TMPDIR, mode 0700) that is
// removed whatever happens (docs/formats.md "Zip archives"): when the object
// goes out of scope, on an exception, and when SIGINT or SIGTERM ends the
// process while it exists. The signal handler may only make
// async-signal-safe calls (unlink, rmdir: POSIX.1-2017 2.4.3), so the files
// and folders to be created inside are declared (Plan) before they are
// written; after removing them the handler gives the signal to the handler
// that was there before (by default the process ends by the signal, the
// conventional status: 130 for SIGINT, 143 for SIGTERM in a shell). A signal
// that was ignored when the folder was made stays ignored. The signal may be
// delivered to any thread, one started later included: what the handler
// reads (the published Removal) is freed only when no handler runs in any
// thread (a count of running handlers, lock-free atomics).
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace napkin::ingest {

class TemporaryFolder {
 public:
  // Creates "<$TMPDIR>/<prefix>XXXXXX". Throws InputError naming `purpose`
  // (e.g. "archive.zip") when it cannot be created.
  TemporaryFolder(const std::string& prefix, const std::string& purpose);
  ~TemporaryFolder();
  TemporaryFolder(const TemporaryFolder&) = delete;
  TemporaryFolder& operator=(const TemporaryFolder&) = delete;

  const std::filesystem::path& path() const { return path_; }

  // Declares the files (relative paths inside the folder, '/' separated) that
  // will be written into it, with their parent folders; replaces the earlier
  // declaration. A signal removes exactly these (and the folder itself).
  void Plan(const std::vector<std::string>& relative_files);

  // What a signal handler removes: absolute paths, files first, then folders
  // deepest first, the temporary folder last. Built before it is published.
  struct Removal {
    std::vector<std::string> files;
    std::vector<std::string> folders;
  };

 private:
  void Publish(std::unique_ptr<const Removal> removal);

  std::filesystem::path path_;
  std::unique_ptr<const Removal> removal_;  // the published one
  int slot_ = -1;                           // its place in the handler's table
};

}  // namespace napkin::ingest
