// The parallel refiner's vertex locks: a failed lock names the thread that holds the vertex, so
// that a worker that rolled back can wait for that thread to let go.
#include "delaunay/vertex_locks.h"

#include <gtest/gtest.h>

#include "delaunay/pentatope_store.h"

namespace mesh4d::delaunay {
namespace {

TEST(VertexLocks, AFailedLockNamesTheHolderUntilTaken) {
  PentatopeStore store;
  const VertexId v = store.add_vertex({0, 0, 0, 0}, VertexKind::feature);
  const VertexId u = store.add_vertex({1, 0, 0, 0}, VertexKind::feature);
  VertexLocks first(store, 1);
  VertexLocks second(store, 2);

  ASSERT_TRUE(first.lock(v));
  EXPECT_TRUE(first.lock(v));  // its own lock again
  EXPECT_FALSE(first.take_blocker().has_value());
  EXPECT_TRUE(second.lock(u));
  EXPECT_FALSE(second.take_blocker().has_value());

  EXPECT_FALSE(second.lock(v));
  const auto blocker = second.take_blocker();
  ASSERT_TRUE(blocker.has_value());
  EXPECT_EQ(blocker->vertex, v);
  EXPECT_EQ(blocker->owner, 1u);
  EXPECT_FALSE(second.take_blocker().has_value());  // taken once
  EXPECT_TRUE(second.still_held(*blocker));

  first.release_all();
  EXPECT_FALSE(second.still_held(*blocker));
  EXPECT_TRUE(second.lock(v));
  // Held again, by another thread than the one named: the wait is over all the same.
  second.release_all();
  VertexLocks third(store, 3);
  ASSERT_TRUE(third.lock(v));
  EXPECT_FALSE(second.still_held(*blocker));
}

}  // namespace
}  // namespace mesh4d::delaunay
