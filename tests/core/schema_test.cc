// The options schemas: equality sees every field a schema names, and enum names round-trip.
#include "core/schema.h"

#include "attention/attention.h"
#include "core/foveation.h"
#include "core/recognition.h"
#include "core/saliency.h"
#include "core/sim/scenario.h"
#include "core/tracking.h"

#include <gtest/gtest.h>

#include <string>

namespace saccade {
namespace {

// Changes the field Serialize visits `target`-th (counting from 0) and counts the fields.
class MutateOne {
 public:
  explicit MutateOne(int target) : target_(target) {}
  template <typename T>
  void Visit(const char* /*name*/, T* field) {
    if (visited_++ == target_) Mutate(field);
  }
  template <typename Enum>
  void Choice(const char* /*name*/, Enum* field, ChoiceNames<Enum> names) {
    if (visited_++ != target_) return;
    for (const auto& [label, value] : names)  // any other named value
      if (value != *field) {
        *field = value;
        return;
      }
  }
  template <typename Options>
  void Section(const char* /*name*/, Options* options) {
    options->Serialize(this);
  }
  int visited() const { return visited_; }

 private:
  void Mutate(bool* f) { *f = !*f; }
  template <typename T>
  std::enable_if_t<std::is_arithmetic_v<T>> Mutate(T* f) {
    *f = static_cast<T>(*f + 1);
  }
  template <typename M>
  void Mutate(Eigen::MatrixBase<M>* m) {
    (*m)(0) += 1;
  }
  void Mutate(Eigen::Vector2f* v) { Mutate(static_cast<Eigen::MatrixBase<Eigen::Vector2f>*>(v)); }
  void Mutate(Eigen::Vector3f* v) { Mutate(static_cast<Eigen::MatrixBase<Eigen::Vector3f>*>(v)); }
  void Mutate(Eigen::Quaternionf* q) { q->w() += 1; }
  void Mutate(std::string* s) { *s += "x"; }

  int target_;
  int visited_ = 0;
};

template <typename Options>
void ExpectEveryFieldCounts(const char* what) {
  SCOPED_TRACE(what);
  MutateOne count(-1);
  Options probe;
  probe.Serialize(&count);
  ASSERT_GT(count.visited(), 0);
  const Options original;
  EXPECT_TRUE(SameFields(original, Options{}));
  for (int k = 0; k < count.visited(); ++k) {
    Options changed;
    MutateOne mutate(k);
    changed.Serialize(&mutate);
    EXPECT_FALSE(SameFields(original, changed)) << "field " << k << " is not compared";
  }
}

TEST(Schema, EqualitySeesEveryFieldTheSchemaNames) {
  ExpectEveryFieldCounts<RecognitionOptions>("recognition");
  ExpectEveryFieldCounts<VerificationOptions>("verification");
  ExpectEveryFieldCounts<FoveaOptions>("fovea");
  ExpectEveryFieldCounts<AttentionOptions>("attention");
  ExpectEveryFieldCounts<SaliencyOptions>("saliency");
  ExpectEveryFieldCounts<KinectNoise>("noise");
  ExpectEveryFieldCounts<Trajectory>("trajectory");
  ExpectEveryFieldCounts<TrackOptions>("tracking");
}

TEST(Schema, OperatorsAgreeWithSameFields) {
  RecognitionOptions a, b;
  EXPECT_TRUE(a == b);
  b.verify.min_confidence += 0.1f;  // a nested struct's field
  EXPECT_TRUE(a != b);
  FoveaOptions f, g;
  g.outer_orientation = Eigen::Quaternionf(Eigen::AngleAxisf(0.1f, Eigen::Vector3f::UnitZ()));
  EXPECT_TRUE(f != g);
}

TEST(Schema, ChoiceNameNamesEachValue) {
  const ChoiceNames<GrowthKind> names = {{"additive", GrowthKind::kAdditive},
                                         {"multiplicative", GrowthKind::kMultiplicative}};
  EXPECT_STREQ(ChoiceName(GrowthKind::kAdditive, names), "additive");
  EXPECT_STREQ(ChoiceName(GrowthKind::kMultiplicative, names), "multiplicative");
  EXPECT_STREQ(ChoiceName(static_cast<GrowthKind>(7), names), "?");
}

}  // namespace
}  // namespace saccade
