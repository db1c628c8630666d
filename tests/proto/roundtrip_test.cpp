// The generated API code is real: a job spec survives the wire format, the upload's oneof keeps
// its case, and the service has the methods the API promises.
#include <google/protobuf/descriptor.h>
#include <google/protobuf/util/message_differencer.h>
#include <gtest/gtest.h>

#include "mesh4d/v1/mesh4d.grpc.pb.h"

namespace {

mesh4d::v1::JobSpec sample_spec() {
  mesh4d::v1::JobSpec spec;
  auto* image = spec.mutable_image();
  image->mutable_dims()->set_x(100);
  image->mutable_dims()->set_y(100);
  image->mutable_dims()->set_z(44);
  image->mutable_dims()->set_t(15);
  image->mutable_spacing()->set_x(1.77);
  image->mutable_spacing()->set_y(1.77);
  image->mutable_spacing()->set_z(6.0);
  image->mutable_spacing()->set_t(1.0);
  image->mutable_origin()->set_x(-12.5);
  image->set_label_type(mesh4d::v1::LABEL_TYPE_UINT16);
  image->set_byte_size(100ull * 100 * 44 * 15 * 2);
  image->set_sha256(std::string(32, '\xab'));
  auto* params = spec.mutable_params();
  params->set_delta(5.0);
  params->set_radius_edge_bound(2.0);
  params->set_rule_order(mesh4d::v1::RULE_ORDER_PAPER);
  params->set_seed(0xfeedfacecafebeefull);
  params->set_vertex_budget(1'000'000);
  params->set_threads(8);
  spec.set_request_id("req-7f3a");
  spec.set_name("heart.nii.gz");
  return spec;
}

TEST(ProtoRoundTrip, JobSpecSurvivesTheWire) {
  const auto spec = sample_spec();
  const std::string wire = spec.SerializeAsString();
  ASSERT_FALSE(wire.empty());
  mesh4d::v1::JobSpec back;
  ASSERT_TRUE(back.ParseFromString(wire));
  EXPECT_TRUE(google::protobuf::util::MessageDifferencer::Equals(spec, back)) << back.DebugString();
  EXPECT_EQ(back.image().spacing().z(), 6.0);
  EXPECT_EQ(back.params().seed(), 0xfeedfacecafebeefull);
}

TEST(ProtoRoundTrip, UploadMessagesKeepTheirCase) {
  mesh4d::v1::SubmitJobRequest first;
  *first.mutable_spec() = sample_spec();
  mesh4d::v1::SubmitJobRequest chunk;
  chunk.set_chunk(std::string("\x00\x01\x02\x00", 4));

  mesh4d::v1::SubmitJobRequest a, b;
  ASSERT_TRUE(a.ParseFromString(first.SerializeAsString()));
  ASSERT_TRUE(b.ParseFromString(chunk.SerializeAsString()));
  EXPECT_EQ(a.payload_case(), mesh4d::v1::SubmitJobRequest::kSpec);
  EXPECT_EQ(b.payload_case(), mesh4d::v1::SubmitJobRequest::kChunk);
  EXPECT_EQ(b.chunk(), std::string("\x00\x01\x02\x00", 4));  // embedded zeros kept
}

TEST(ProtoRoundTrip, TruncatedMessageIsRejected) {
  const std::string wire = sample_spec().SerializeAsString();
  mesh4d::v1::JobSpec back;
  EXPECT_FALSE(back.ParseFromString(wire.substr(0, wire.size() - 3)));
}

TEST(ProtoRoundTrip, ServiceDescribesEveryMethod) {
  const auto* service = google::protobuf::DescriptorPool::generated_pool()->FindServiceByName(
      "mesh4d.v1.MeshService");
  ASSERT_NE(service, nullptr);
  EXPECT_EQ(service->full_name(), "mesh4d.v1.MeshService");
  for (const char* name :
       {"SubmitJob", "GetJob", "WatchJob", "CancelJob", "ListJobs", "GetResult", "DeleteJob"})
    EXPECT_NE(service->FindMethodByName(name), nullptr) << name;
  EXPECT_TRUE(service->FindMethodByName("SubmitJob")->client_streaming());
  EXPECT_TRUE(service->FindMethodByName("WatchJob")->server_streaming());
  EXPECT_TRUE(service->FindMethodByName("GetResult")->server_streaming());
}

}  // namespace
