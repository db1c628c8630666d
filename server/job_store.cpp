#include "job_store.h"

#include <fstream>
#include <sstream>
#include <system_error>

#include "atomic_file.h"

namespace mesh4d::server {
namespace {

constexpr const char* kRecord = "job.pb";
constexpr const char* kInput = "input.bin";
constexpr const char* kResult = "result.m4d";

std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::system_error(errno, std::generic_category(), "cannot open " + path.string());
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

JobStore::JobStore(std::filesystem::path root) : root_(std::move(root)), jobs_(root_ / "jobs") {
  std::filesystem::create_directories(jobs_);
}

std::vector<v1::Job> JobStore::load_all(std::vector<std::string>* problems) {
  std::vector<v1::Job> jobs;
  for (const auto& entry : std::filesystem::directory_iterator(jobs_)) {
    if (!entry.is_directory()) continue;
    const auto record = entry.path() / kRecord;
    if (!std::filesystem::exists(record)) {
      // Created but never acknowledged (the crash came before job.pb): nothing to keep.
      std::filesystem::remove_all(entry.path());
      continue;
    }
    v1::Job job;
    if (!job.ParseFromString(read_text(record)) || job.id() != entry.path().filename().string()) {
      if (problems) problems->push_back("unreadable job record " + record.string());
      continue;
    }
    jobs.push_back(std::move(job));
  }
  return jobs;
}

void JobStore::create(const v1::Job& job, std::string_view input) {
  const auto d = dir(job.id());
  std::filesystem::create_directories(d);
  sync_directory(jobs_);
  write_file_atomically(d / kInput, input);
  save(job);
}

void JobStore::save(const v1::Job& job) {
  write_file_atomically(dir(job.id()) / kRecord, job.SerializeAsString());
}

void JobStore::save_result(const std::string& id, std::string_view mesh) {
  write_file_atomically(dir(id) / kResult, mesh);
}

std::string JobStore::read_input(const std::string& id) const {
  return read_text(dir(id) / kInput);
}

std::string JobStore::read_result(const std::string& id) const {
  return read_text(dir(id) / kResult);
}

void JobStore::remove(const std::string& id) {
  // The record goes first: a crash half-way leaves a directory without job.pb, cleaned at load.
  std::error_code ec;
  std::filesystem::remove(dir(id) / kRecord, ec);
  std::filesystem::remove_all(dir(id), ec);
}

}  // namespace mesh4d::server
