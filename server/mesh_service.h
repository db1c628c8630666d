// The gRPC face of the job service (mesh4d.v1.MeshService): decodes requests, calls the
// JobManager, maps wire::ServiceError to status codes. No job logic lives here.
#pragma once

#include <string>

#include "job_manager.h"
#include "mesh4d/v1/mesh4d.grpc.pb.h"

namespace mesh4d::server {

class MeshService final : public v1::MeshService::Service {
 public:
  /// `token`: when not empty, every call must carry "authorization: Bearer <token>".
  MeshService(JobManager& jobs, std::string token, JobObserver* observer = nullptr)
      : jobs_(jobs), token_(std::move(token)), observer_(observer) {}

  grpc::Status SubmitJob(grpc::ServerContext* context,
                         grpc::ServerReader<v1::SubmitJobRequest>* reader,
                         v1::SubmitJobResponse* response) override;
  grpc::Status GetJob(grpc::ServerContext* context, const v1::GetJobRequest* request,
                      v1::Job* response) override;
  grpc::Status WatchJob(grpc::ServerContext* context, const v1::WatchJobRequest* request,
                        grpc::ServerWriter<v1::JobEvent>* writer) override;
  grpc::Status CancelJob(grpc::ServerContext* context, const v1::CancelJobRequest* request,
                         v1::Job* response) override;
  grpc::Status ListJobs(grpc::ServerContext* context, const v1::ListJobsRequest* request,
                        v1::ListJobsResponse* response) override;
  grpc::Status GetResult(grpc::ServerContext* context, const v1::GetResultRequest* request,
                         grpc::ServerWriter<v1::GetResultResponse>* writer) override;
  grpc::Status DeleteJob(grpc::ServerContext* context, const v1::DeleteJobRequest* request,
                         v1::DeleteJobResponse* response) override;

 private:
  grpc::Status authorize(const grpc::ServerContext* context) const;

  JobManager& jobs_;
  std::string token_;
  JobObserver* observer_;
};

}  // namespace mesh4d::server
