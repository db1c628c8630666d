// The durable side of the job queue: one directory per job under <data>/jobs/<id>/ with the job
// record (job.pb, the Job message), the uploaded labels (input.bin) and, once done, the mesh
// (result.m4d). Every file is written atomically (atomic_file.h). A job exists, for a restarted
// server, exactly when its job.pb does: it is written last when a job is created.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "mesh4d/v1/mesh4d.pb.h"

namespace mesh4d::server {

class JobStore {
 public:
  /// Creates <root>/jobs when missing. Throws std::system_error when it cannot.
  explicit JobStore(std::filesystem::path root);

  /// Every stored job; directories left half-written by a crash are removed, unreadable records
  /// are skipped and reported in `problems`.
  std::vector<v1::Job> load_all(std::vector<std::string>* problems);

  /// Stores a new job: its input first, then its record.
  void create(const v1::Job& job, std::string_view input);
  /// Replaces a job's record.
  void save(const v1::Job& job);
  void save_result(const std::string& id, std::string_view mesh);

  std::string read_input(const std::string& id) const;
  std::string read_result(const std::string& id) const;
  void remove(const std::string& id);

  const std::filesystem::path& root() const { return root_; }

 private:
  std::filesystem::path dir(const std::string& id) const { return jobs_ / id; }

  std::filesystem::path root_;
  std::filesystem::path jobs_;
};

}  // namespace mesh4d::server
