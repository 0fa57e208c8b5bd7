#include "attention/attention.h"

#include <gtest/gtest.h>

#include <random>

namespace saccade {
namespace {

// A detection of `model` whose centroid is at (x, y, z): all attention reads of it.
Detection At(float x, float y, float z, int model = 0) {
  Detection d;
  d.model = model;
  d.centroid_m = Eigen::Vector3f(x, y, z);
  return d;
}

TEST(Attention, FollowsTheSightingNearestThePreviousFovea) {
  Attention a(AttentionOptions{}, Eigen::Vector3f(0, 0, 1));
  const Fixation f = a.Update(1, 0.0, {At(1, 0, 1), At(0.1f, 0, 1)});
  EXPECT_EQ(f.mode, AttentionMode::kTracking);
  EXPECT_EQ(f.reason, "detected");
  EXPECT_EQ(f.frame_seq, 1);
  EXPECT_TRUE(f.fovea_m.isApprox(Eigen::Vector3f(0.1f, 0, 1)));
  EXPECT_EQ(f.growth_m, 0.0f);
  // The next frame it keeps the same target, now near (1, 0, 1) no more: the nearer one wins.
  const Fixation g = a.Update(2, 0.1, {At(0.9f, 0, 1), At(0.15f, 0, 1)});
  EXPECT_EQ(g.target, f.target);
  EXPECT_TRUE(g.fovea_m.isApprox(Eigen::Vector3f(0.15f, 0, 1)));
}

TEST(Attention, GrowsAdditivelyWhileLostThenFallsBackToFullScanAndRecovers) {
  AttentionOptions o;
  o.growth_step = 0.25f;
  o.growth_max_m = 1.0f;
  Attention a(o, Eigen::Vector3f(0, 0, 1));
  a.Update(1, 0.0, {At(0.2f, 0, 1)});
  const std::vector<float> expected = {0.25f, 0.5f, 0.75f, 1.0f};
  for (std::size_t i = 0; i < expected.size(); ++i) {
    const Fixation f = a.Update(2 + i, 0.0, {});
    EXPECT_EQ(f.mode, AttentionMode::kSearching);
    EXPECT_EQ(f.reason, i == 0 ? "lost" : "grow");
    EXPECT_FLOAT_EQ(f.growth_m, expected[i]);
    EXPECT_TRUE(f.fovea_m.isApprox(Eigen::Vector3f(0.2f, 0, 1)));  // stays where it was
  }
  EXPECT_EQ(a.Update(6, 0.0, {}).mode, AttentionMode::kFullScan);
  EXPECT_EQ(a.Update(7, 0.0, {}).mode, AttentionMode::kFullScan);
  const Fixation back = a.Update(8, 0.0, {At(0.5f, 0, 1)});
  EXPECT_EQ(back.mode, AttentionMode::kTracking);
  EXPECT_EQ(back.growth_m, 0.0f);
  EXPECT_TRUE(back.fovea_m.isApprox(Eigen::Vector3f(0.5f, 0, 1)));
}

TEST(Attention, GrowsMultiplicativelyFromTheFloor) {
  AttentionOptions o;
  o.growth_kind = GrowthKind::kMultiplicative;
  o.growth_step = 2.0f;
  o.growth_floor_m = 0.05f;
  o.growth_max_m = 0.3f;
  Attention a(o, Eigen::Vector3f(0, 0, 1));
  std::vector<float> g;
  for (int i = 0; i < 4; ++i) g.push_back(a.Update(i, 0.0, {}).growth_m);
  EXPECT_FLOAT_EQ(g[0], 0.1f);
  EXPECT_FLOAT_EQ(g[1], 0.2f);
  EXPECT_FLOAT_EQ(g[2], 0.3f);  // capped at G_max
  EXPECT_EQ(a.current().mode, AttentionMode::kFullScan);
}

TEST(Attention, SaccadeFallbackVisitsSalientRegionsOnceEachMostSalientFirst) {
  AttentionOptions o;
  o.growth_step = 0.5f;
  o.growth_max_m = 0.5f;
  o.fallback = LostFallback::kSaccade;
  o.search = SearchKind::kGrow;  // G grows first: the salient regions are the fallback's
  const Eigen::Vector3f start(0, 0, 1);
  Attention a(o, start);
  const std::vector<Eigen::Vector3f> salient = {
      Eigen::Vector3f(0.05f, 0, 1),  // where the fovea already is: not a new region
      Eigen::Vector3f(0.5f, 0, 1), Eigen::Vector3f(-0.5f, 0, 1), Eigen::Vector3f(0.52f, 0, 1)};
  EXPECT_EQ(a.Update(0, 0.0, {}, salient).reason, "grow");  // G: 0 -> 0.5 = G_max
  std::vector<Eigen::Vector3f> visits;
  for (int i = 1; i <= 3; ++i) {
    const Fixation f = a.Update(i, 0.0, {}, salient);
    EXPECT_EQ(f.reason, "saccade");
    EXPECT_EQ(f.mode, AttentionMode::kSearching);
    EXPECT_EQ(f.growth_m, 0.0f);
    visits.push_back(f.fovea_m);
  }
  EXPECT_TRUE(visits[0].isApprox(salient[1]));
  EXPECT_TRUE(visits[1].isApprox(salient[2]));
  // Everything has been seen once: the search starts over, not at the region it stands on.
  EXPECT_FALSE(visits[2].isApprox(visits[1]));
  const Fixation found = a.Update(4, 0.0, {At(-0.4f, 0, 1)}, salient);
  EXPECT_EQ(found.mode, AttentionMode::kTracking);
  EXPECT_TRUE(found.fovea_m.isApprox(Eigen::Vector3f(-0.4f, 0, 1)));
}

// Issue 34's search: with no target known, the fovea visits the frame's candidates best first
// (once each, at G_min), follows a sighting at once only at acquire_confidence, and once the
// candidates are visited follows the most confident weaker sighting it saw; then G grows.
Detection Seen(float x, float confidence) {
  Detection d = At(x, 0, 1);
  d.confidence = confidence;
  return d;
}

TEST(Attention, ASearchVisitsCandidatesBestFirstThenFollowsTheMostConfidentSighting) {
  AttentionOptions o;
  o.max_candidate_visits = 3;
  Attention a(o, Eigen::Vector3f(0, 0, 1));
  const std::vector<Eigen::Vector3f> places = {
      Eigen::Vector3f(0.4f, 0, 1), Eigen::Vector3f(-0.4f, 0, 1), Eigen::Vector3f(0.8f, 0, 1),
      Eigen::Vector3f(-0.8f, 0, 1)};
  // The initial fovea, a guess with no candidate within reach, lands on the best: the first visit.
  Fixation f = a.Update(1, 0.0, {}, places);
  EXPECT_EQ(f.reason, "candidate");
  EXPECT_EQ(f.mode, AttentionMode::kSearching);
  EXPECT_TRUE(f.fovea_m.isApprox(places[0]));
  EXPECT_EQ(f.growth_m, 0.0f);
  f = a.Update(2, 0.1, {Seen(0.4f, 0.6f)}, places);  // too weak to follow at once
  EXPECT_EQ(f.reason, "candidate");
  EXPECT_TRUE(f.fovea_m.isApprox(places[1]));
  f = a.Update(3, 0.2, {Seen(-0.4f, 0.8f)}, places);  // weaker than the bar, but the best yet
  EXPECT_TRUE(f.fovea_m.isApprox(places[2]));
  f = a.Update(4, 0.3, {Seen(0.8f, 0.5f)}, places);  // three visited: follow the best seen
  EXPECT_EQ(f.reason, "tentative");
  EXPECT_EQ(f.mode, AttentionMode::kTracking);
  EXPECT_TRUE(f.fovea_m.isApprox(Eigen::Vector3f(-0.4f, 0, 1)));
  f = a.Update(5, 0.4, {Seen(-0.41f, 0.8f)}, places);
  EXPECT_EQ(f.reason, "detected");
  EXPECT_EQ(f.mode, AttentionMode::kTracking);
}

TEST(Attention, AConfidentSightingIsFollowedAtOnceAndAWeakOneNot) {
  const std::vector<Eigen::Vector3f> places = {Eigen::Vector3f(0.4f, 0, 1)};
  Attention a(AttentionOptions{}, Eigen::Vector3f(0, 0, 1));
  EXPECT_EQ(a.Update(1, 0.0, {Seen(0.1f, 0.89f)}, places).reason, "candidate");
  const Fixation f = a.Update(2, 0.1, {Seen(0.1f, 0.89f), Seen(0.4f, 0.95f)}, places);
  EXPECT_EQ(f.reason, "detected");
  EXPECT_TRUE(f.fovea_m.isApprox(Eigen::Vector3f(0.4f, 0, 1)));
  // Unverified sightings (no confidence) and a bar of 0 follow the first sighting, as the paper.
  Attention paper(AttentionOptions{}, Eigen::Vector3f(0, 0, 1));
  EXPECT_EQ(paper.Update(1, 0.0, {At(0.1f, 0, 1)}, places).reason, "detected");
}

TEST(Attention, NoCandidatesOrSearchGrowGrowsGAsThePaper) {
  AttentionOptions o;
  Attention none(o, Eigen::Vector3f(0, 0, 1));
  EXPECT_EQ(none.Update(1, 0.0, {}, {}).reason, "grow");
  o.search = SearchKind::kGrow;
  Attention grow(o, Eigen::Vector3f(0, 0, 1));
  const Fixation f = grow.Update(1, 0.0, {}, {Eigen::Vector3f(0.4f, 0, 1)});
  EXPECT_EQ(f.reason, "grow");
  EXPECT_TRUE(f.fovea_m.isApprox(Eigen::Vector3f(0, 0, 1)));
}

TEST(Attention, ALostTargetIsSearchedWhereItWasNotAtTheCandidates) {
  Attention a(AttentionOptions{}, Eigen::Vector3f(0, 0, 1));
  a.Update(1, 0.0, {Seen(0.1f, 0.95f)});
  const Fixation f = a.Update(2, 0.1, {}, {Eigen::Vector3f(0.5f, 0, 1)});
  EXPECT_EQ(f.reason, "lost");
  EXPECT_TRUE(f.fovea_m.isApprox(Eigen::Vector3f(0.1f, 0, 1)));
  EXPECT_GT(f.growth_m, 0.0f);
}

TEST(Attention, AClearlyMoreConfidentSightingTakesTheTargetOver) {
  Attention a(AttentionOptions{}, Eigen::Vector3f(0, 0, 1));
  a.Update(1, 0.0, {Seen(0.1f, 0.9f)});
  // Not clearly more confident (0.95 < 0.9 + 0.15): the nearer sighting stays the target.
  Fixation f = a.Update(2, 0.1, {Seen(0.1f, 0.9f), Seen(0.5f, 0.95f)});
  EXPECT_EQ(f.reason, "detected");
  EXPECT_TRUE(f.fovea_m.isApprox(Eigen::Vector3f(0.1f, 0, 1)));
  a.Update(3, 0.2, {Seen(0.1f, 0.8f)});
  f = a.Update(4, 0.3, {Seen(0.1f, 0.8f), Seen(0.5f, 0.96f)});
  EXPECT_EQ(f.reason, "challenged");
  EXPECT_TRUE(f.fovea_m.isApprox(Eigen::Vector3f(0.5f, 0, 1)));
}

TEST(Attention, AnAimedFixationLandsOnTheNearestCandidateWithinReach) {
  const std::vector<Eigen::Vector3f> places = {Eigen::Vector3f(0.3f, 0, 1),
                                               Eigen::Vector3f(0.12f, 0, 1)};
  const Eigen::Vector3f aim(0, 0, 1);
  EXPECT_TRUE(LandOnCandidate(aim, places, 0.2f).isApprox(places[1]));
  EXPECT_TRUE(LandOnCandidate(aim, places, 0.1f).isApprox(aim));
  EXPECT_TRUE(LandOnCandidate(aim, {}, 1.0f).isApprox(aim));
  // One already this near: the aim is on an object, and stays.
  EXPECT_TRUE(LandOnCandidate(aim, places, 0.2f, 0.15f).isApprox(aim));
}

// Landing within 25 cm, none of it a stay; the best candidate 50 cm from (0, 0, 1), the other
// 14 cm.
AttentionOptions LandingOptions() {
  AttentionOptions o;
  o.land_on_candidate_m = 0.25f;
  o.land_stay_m = 0;
  return o;
}
const std::vector<Eigen::Vector3f> kLandingPlaces = {Eigen::Vector3f(0.5f, 0, 1),
                                                     Eigen::Vector3f(0.1f, 0, 1.1f)};

TEST(Attention, AGivenFoveaLandsOnTheNearestCandidateFirst) {
  const std::vector<Eigen::Vector3f>& places = kLandingPlaces;
  Attention a(LandingOptions(), Eigen::Vector3f(0, 0, 1));
  Fixation f = a.Update(1, 0.0, {}, places);
  EXPECT_EQ(f.reason, "landed");
  EXPECT_TRUE(f.fovea_m.isApprox(places[1]));
  f = a.Update(2, 0.1, {}, places);  // then the candidates, best first
  EXPECT_EQ(f.reason, "candidate");
  EXPECT_TRUE(f.fovea_m.isApprox(places[0]));
  a.Reset(Eigen::Vector3f(0.45f, 0, 1), "command", /*aimed=*/true);
  EXPECT_TRUE(a.Update(3, 0.2, {}, places).fovea_m.isApprox(places[0]));
}

// A guessed fovea (the initial one, a reset) with no candidate within reach lands on the best
// of them; an aimed one (a command) stays where it was aimed; either lands on one within reach.
TEST(Attention, AGuessedFoveaLandsOnTheBestCandidateAndAnAimedOneStays) {
  const std::vector<Eigen::Vector3f> places = {Eigen::Vector3f(0.6f, 0, 1),
                                               Eigen::Vector3f(0.12f, 0, 1)};
  Fixation guess;
  guess.fovea_m = Eigen::Vector3f(0, 0, 1);
  guess.lands = true;
  Fixation aim = guess;
  aim.aimed = true;
  EXPECT_TRUE(LandGiven(guess, places, 0.1f, 0).isApprox(places[0]));
  EXPECT_TRUE(LandGiven(aim, places, 0.1f, 0).isApprox(aim.fovea_m));
  EXPECT_TRUE(LandGiven(guess, places, 0.2f, 0).isApprox(places[1]));
  EXPECT_TRUE(LandGiven(aim, places, 0.2f, 0).isApprox(places[1]));
  EXPECT_TRUE(LandGiven(guess, {}, 0.2f, 0).isApprox(guess.fovea_m));
  EXPECT_TRUE(LandGiven(guess, places, 0, 0).isApprox(guess.fovea_m));  // landing off
}

// saccaded lands a given fovea in the frame it is given for (Attention::Landed): the search
// counts that landing, so the next frame visits the next candidate, not the same one again; a
// landing for a fovea given since (a command) is not this one's.
TEST(Attention, ALandingMadeByTheFrameIsCountedOnce) {
  const std::vector<Eigen::Vector3f>& places = kLandingPlaces;
  const Eigen::Vector3f start(0, 0, 1);
  Attention a(LandingOptions(), start);
  EXPECT_TRUE(a.current().lands);
  a.Landed(start, places[1]);
  EXPECT_FALSE(a.current().lands);
  EXPECT_EQ(a.current().reason, "landed");
  EXPECT_TRUE(a.current().fovea_m.isApprox(places[1]));
  a.Landed(start, places[0]);  // once only
  EXPECT_TRUE(a.current().fovea_m.isApprox(places[1]));
  Fixation f = a.Update(1, 0.0, {}, places);
  EXPECT_EQ(f.reason, "candidate");
  EXPECT_TRUE(f.fovea_m.isApprox(places[0]));

  const Eigen::Vector3f asked(0.45f, 0, 1);
  a.Reset(asked, "command", /*aimed=*/true);
  EXPECT_TRUE(a.current().aimed);
  a.Landed(start, places[1]);  // landed for the fovea before the command: not this one's
  EXPECT_TRUE(a.current().lands);
  EXPECT_TRUE(a.current().fovea_m.isApprox(asked));
  // A target followed: nothing left to land.
  f = a.Update(2, 0.1, {Seen(0.45f, 0.95f)}, places);
  EXPECT_EQ(f.mode, AttentionMode::kTracking);
  EXPECT_FALSE(f.lands);
}

TEST(Attention, ASearchFrameLooksAtItsNextCandidatesUntilOneHoldsTheObject) {
  AttentionOptions o;
  o.looks_per_frame = 4;
  const std::vector<Eigen::Vector3f> places = {
      Eigen::Vector3f(0.4f, 0, 1), Eigen::Vector3f(-0.4f, 0, 1), Eigen::Vector3f(0.8f, 0, 1),
      Eigen::Vector3f(-0.8f, 0, 1)};
  AttentionOptions paper;
  paper.looks_per_frame = 1;
  EXPECT_EQ(Attention(paper, Eigen::Vector3f(0, 0, 1)).PlanLooks().left, 0);
  EXPECT_EQ(Attention(AttentionOptions{}, Eigen::Vector3f(0, 0, 1)).PlanLooks().left, 2);
  Attention a(o, Eigen::Vector3f(0, 0, 1));
  Fixation f = a.Update(1, 0.0, {}, places);  // the guess lands on the best: the first visit
  ASSERT_TRUE(f.fovea_m.isApprox(places[0]));
  const Looks plan = a.PlanLooks();
  EXPECT_EQ(plan.left, 3);
  // The frame's first look, at places[0], saw nothing; the next sees a weak sighting there and
  // the object farther on, weakly; the one after sees the object well: the frame stops there.
  std::vector<Detection> found;
  std::vector<Eigen::Vector3f> asked;
  const std::vector<Eigen::Vector3f> looks = plan.Take(
      places[0], places, &found, [&](const Eigen::Vector3f& place, std::vector<Detection>* out) {
        asked.push_back(place);
        if (place == places[1]) out->push_back(Seen(-0.4f, 0.6f));
        if (place == places[1]) out->push_back(Seen(0.8f, 0.5f));
        if (place == places[2]) out->push_back(Seen(0.81f, 0.95f));
      });
  ASSERT_EQ(looks.size(), 2u);
  EXPECT_EQ(asked, looks);
  EXPECT_TRUE(looks[0].isApprox(places[1]));
  EXPECT_TRUE(looks[1].isApprox(places[2]));
  ASSERT_EQ(found.size(), 2u);  // the object seen twice is kept once, its better sighting
  EXPECT_FLOAT_EQ(found[0].confidence, 0.6f);
  EXPECT_FLOAT_EQ(found[1].confidence, 0.95f);
  a.Looked(7, places[0], looks);  // another frame's looks: ignored
  EXPECT_TRUE(a.current().fovea_m.isApprox(places[0]));
  a.Looked(1, places[0], looks);
  EXPECT_TRUE(a.current().fovea_m.isApprox(places[2]));
  EXPECT_EQ(a.current().reason, "candidate");
  f = a.Update(2, 0.1, found, places);
  EXPECT_EQ(f.mode, AttentionMode::kTracking);
  EXPECT_EQ(f.reason, "detected");
  EXPECT_TRUE(f.fovea_m.isApprox(Eigen::Vector3f(0.81f, 0, 1)));
  EXPECT_EQ(a.PlanLooks().left, 0);  // following a target: no looks elsewhere

  // The looks are candidate visits: the search's budget bounds them, and a frame looks only
  // where this search has not.
  o.max_candidate_visits = 3;
  Attention b(o, Eigen::Vector3f(0, 0, 1));
  b.Update(1, 0.0, {}, places);
  const Looks two = b.PlanLooks();
  EXPECT_EQ(two.left, 2);
  std::vector<Detection> none;
  const auto blind = [](const Eigen::Vector3f&, std::vector<Detection>*) {};
  b.Looked(1, places[0], two.Take(places[0], places, &none, blind));
  f = b.Update(2, 0.1, {}, places);
  EXPECT_NE(f.reason, "candidate");  // three visited: G grows
  EXPECT_GT(f.growth_m, 0.0f);
}

// A frame whose time is spent (may_look false) takes no further look: the place it did not
// look at is not counted as looked at, and the next frame's looks start there.
TEST(Attention, AFrameWhoseTimeIsSpentStopsLooking) {
  const std::vector<Eigen::Vector3f> places = {
      Eigen::Vector3f(0.4f, 0, 1), Eigen::Vector3f(-0.4f, 0, 1), Eigen::Vector3f(0.8f, 0, 1)};
  Looks plan;
  plan.left = 2;
  std::vector<Detection> none;
  std::vector<Eigen::Vector3f> asked;
  const auto look = [&](const Eigen::Vector3f& place, std::vector<Detection>*) {
    asked.push_back(place);
  };
  int allowed = 1;
  const std::vector<Eigen::Vector3f> looks =
      plan.Take(places[0], places, &none, look, [&] { return allowed-- > 0; });
  ASSERT_EQ(looks.size(), 1u);
  EXPECT_EQ(asked, looks);
  EXPECT_TRUE(looks[0].isApprox(places[1]));
  asked.clear();
  EXPECT_TRUE(plan.Take(places[0], places, &none, look, [] { return false; }).empty());
  EXPECT_TRUE(asked.empty());
  EXPECT_EQ(plan.Take(places[0], places, &none, look).size(), 2u);  // no limit given
}

TEST(Attention, ALostTargetsSearchLooksAtCandidatesBesideWhereItWasLost) {
  AttentionOptions o;  // three looks a frame, eight candidate visits
  const std::vector<Eigen::Vector3f> places = {
      Eigen::Vector3f(0.4f, 0, 1), Eigen::Vector3f(-0.4f, 0, 1), Eigen::Vector3f(0.8f, 0, 1),
      Eigen::Vector3f(-0.8f, 0, 1)};
  Attention a(o, Eigen::Vector3f(0, 0, 1));
  a.Update(1, 0.0, {Seen(0.0f, 0.95f)}, places);
  EXPECT_EQ(a.PlanLooks().left, 0);           // following a target
  Fixation f = a.Update(2, 0.1, {}, places);  // lost: G grows where it was
  ASSERT_EQ(f.reason, "lost");
  const Eigen::Vector3f where = f.fovea_m;
  const Looks plan = a.PlanLooks();
  EXPECT_EQ(plan.left, 2);
  EXPECT_FALSE(plan.moves_fovea);
  std::vector<Detection> none;
  const std::vector<Eigen::Vector3f> looks =
      plan.Take(where, places, &none, [](const Eigen::Vector3f&, std::vector<Detection>*) {});
  ASSERT_EQ(looks.size(), 2u);
  a.Looked(2, where, looks);
  EXPECT_TRUE(a.current().fovea_m.isApprox(where));  // the fovea stays, G keeps growing
  f = a.Update(3, 0.2, {}, places);
  EXPECT_TRUE(f.fovea_m.isApprox(where));
  EXPECT_GT(f.growth_m, 0.1f);
  // The next frame looks at the candidates not looked at yet.
  const std::vector<Eigen::Vector3f> next = a.PlanLooks().Take(
      where, places, &none, [](const Eigen::Vector3f&, std::vector<Detection>*) {});
  ASSERT_EQ(next.size(), 2u);
  EXPECT_TRUE(next[0].isApprox(places[2]));
  EXPECT_TRUE(next[1].isApprox(places[3]));
  // Seen at a candidate, it is followed there.
  f = a.Update(4, 0.3, {Seen(0.8f, 0.95f)}, places);
  EXPECT_EQ(f.mode, AttentionMode::kTracking);
  EXPECT_TRUE(f.fovea_m.isApprox(Eigen::Vector3f(0.8f, 0, 1)));
}

TEST(Attention, AlternatesBetweenInstancesAndModelsOnePerFrame) {
  AttentionOptions o;
  o.max_targets = 3;
  Attention a(o, Eigen::Vector3f(0, 0, 1));
  const std::vector<Detection> seen = {At(-0.3f, 0, 1, 0), At(0.3f, 0, 1, 0), At(0, 0, 1.5f, 1)};
  Fixation f = a.Update(0, 0.0, seen);
  EXPECT_EQ(f.num_targets, 3);
  std::vector<int> order;
  for (int i = 1; i <= 6; ++i) {
    f = a.Update(i, i / 30.0, seen);
    EXPECT_EQ(f.mode, AttentionMode::kTracking);
    EXPECT_EQ(f.reason, "alternate");
    order.push_back(f.target);
  }
  // Each target once in every three frames, in a fixed cycle.
  for (int i = 0; i < 3; ++i) EXPECT_EQ(order[i], order[i + 3]);
  EXPECT_NE(order[0], order[1]);
  EXPECT_NE(order[1], order[2]);
  EXPECT_NE(order[0], order[2]);
}

TEST(Attention, GivesUpALostTargetAmongSeveralAndVisitsTheNext) {
  AttentionOptions o;
  o.max_targets = 2;
  o.growth_step = 0.5f;
  o.growth_max_m = 0.5f;
  Attention a(o, Eigen::Vector3f(0, 0, 1));
  a.Update(0, 0.0, {At(-0.3f, 0, 1), At(0.3f, 0, 1)});
  const int followed = a.current().target;
  const Detection other = At(-a.current().fovea_m.x(), 0, 1);
  // The followed target vanishes; the other stays visible but is not looked at.
  const Fixation lost = a.Update(1, 0.0, {other});
  EXPECT_EQ(lost.mode, AttentionMode::kSearching);
  EXPECT_EQ(lost.target, followed);
  const Fixation next = a.Update(2, 0.0, {other});  // G was at G_max: give it up
  EXPECT_EQ(next.reason, "lost");
  EXPECT_EQ(next.mode, AttentionMode::kTracking);
  EXPECT_NE(next.target, followed);
  EXPECT_EQ(next.num_targets, 1);
  EXPECT_TRUE(next.fovea_m.isApprox(other.centroid_m));
}

TEST(Attention, PredictorLeadsAMovingTargetAndIsOffByDefault) {
  const double dt = 1.0 / 30;
  const Eigen::Vector3f v(0.3f, 0, 0.1f);
  for (bool predict : {false, true}) {
    AttentionOptions o;
    o.predict = predict;
    Attention a(o, Eigen::Vector3f(0, 0, 1));
    Fixation f;
    for (int i = 0; i < 10; ++i) {
      const Eigen::Vector3f p = Eigen::Vector3f(0, 0, 1) + v * float(i * dt);
      f = a.Update(i, i * dt, {At(p.x(), p.y(), p.z())});
    }
    const Eigen::Vector3f truth_next = Eigen::Vector3f(0, 0, 1) + v * float(11 * dt);
    const float error = (f.FoveaAt(11 * dt, o.predict_max_horizon_s) - truth_next).norm();
    if (predict) {
      EXPECT_TRUE(f.velocity_mps.isApprox(v, 1e-3f));
      EXPECT_LT(error, 1e-3f);
    } else {
      EXPECT_EQ(f.velocity_mps, Eigen::Vector3f::Zero());
      EXPECT_NEAR(error, (v * float(2 * dt)).norm(), 1e-4f);  // two frames behind
    }
  }
}

TEST(Attention, PredictorLeadIsCappedByItsHorizon) {
  Fixation f;
  f.time_s = 1.0;
  f.fovea_m = Eigen::Vector3f(0, 0, 1);
  f.velocity_mps = Eigen::Vector3f(1, 0, 0);
  EXPECT_TRUE(f.FoveaAt(1.1, 0.2).isApprox(Eigen::Vector3f(0.1f, 0, 1)));
  EXPECT_TRUE(f.FoveaAt(5.0, 0.2).isApprox(Eigen::Vector3f(0.2f, 0, 1)));
  EXPECT_TRUE(f.FoveaAt(0.5, 0.2).isApprox(Eigen::Vector3f(0, 0, 1)));  // never backwards
}

// Over seeded random sequences of sightings, the record stays consistent with the rules.
TEST(Attention, InvariantsHoldOverRandomSequences) {
  for (unsigned seed = 1; seed <= 20; ++seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> pos(-1, 1);
    AttentionOptions o;
    o.growth_step = 0.1f;
    o.growth_max_m = 0.6f;
    o.max_targets = 1 + seed % 3;
    o.predict = seed % 2;
    o.fallback = seed % 4 < 2 ? LostFallback::kFullScan : LostFallback::kSaccade;
    Attention a(o, Eigen::Vector3f(0, 0, 1));
    Fixation previous = a.current();
    for (int i = 0; i < 200; ++i) {
      std::vector<Detection> seen;
      const int n = std::bernoulli_distribution(0.4)(rng) ? 1 + rng() % 3 : 0;
      for (int k = 0; k < n; ++k) {
        const int model = o.max_targets > 1 ? rng() % 2 : 0;
        seen.push_back(At(pos(rng), pos(rng), 1 + pos(rng), model));
      }
      const Fixation f = a.Update(i, i / 30.0, seen, {Eigen::Vector3f(pos(rng), 0, 1)});
      ASSERT_EQ(f.frame_seq, i);
      ASSERT_GE(f.growth_m, o.growth_min_m);
      ASSERT_LE(f.growth_m, o.growth_max_m);
      ASSERT_LE(f.num_targets, o.max_targets);
      if (f.mode == AttentionMode::kTracking) {
        ASSERT_EQ(f.growth_m, o.growth_min_m);
        ASSERT_GE(f.target, 0);
      }
      if (seen.empty() && f.reason == "grow") {
        ASSERT_GE(f.growth_m, previous.growth_m);
      }
      if (o.max_targets == 1 && !seen.empty()) {  // one target of one model: any sighting is it
        ASSERT_EQ(f.mode, AttentionMode::kTracking);
      }
      if (!o.predict) {
        ASSERT_EQ(f.velocity_mps, Eigen::Vector3f::Zero());
      }
      previous = f;
    }
  }
}

TEST(Attention, ResetAndNewOptionsKeepTheRecordInRange) {
  AttentionOptions o;
  o.growth_step = 0.4f;
  Attention a(o, Eigen::Vector3f(0, 0, 1));
  a.Update(0, 0.0, {});
  a.Update(1, 0.0, {});
  EXPECT_FLOAT_EQ(a.current().growth_m, 0.8f);
  o.growth_max_m = 0.5f;
  a.SetOptions(o);
  EXPECT_FLOAT_EQ(a.current().growth_m, 0.5f);
  a.Update(2, 0.0, {At(0, 0, 1)});
  a.Reset(Eigen::Vector3f(1, 0, 2), "command", /*aimed=*/true);
  EXPECT_EQ(a.current().reason, "command");
  EXPECT_EQ(a.current().mode, AttentionMode::kSearching);
  EXPECT_EQ(a.current().target, -1);
  EXPECT_EQ(a.current().num_targets, 0);
  EXPECT_TRUE(a.current().fovea_m.isApprox(Eigen::Vector3f(1, 0, 2)));
}

TEST(AttentionOptions, RejectsBadValuesNamingTheField) {
  const auto error_of = [](AttentionOptions o) {
    std::string error;
    EXPECT_FALSE(o.IsValid(&error));
    return error;
  };
  AttentionOptions o;
  o.growth_step = 0;
  EXPECT_NE(error_of(o).find("growth_step"), std::string::npos);
  o = AttentionOptions{};
  o.growth_kind = GrowthKind::kMultiplicative;
  o.growth_step = 0.5f;
  EXPECT_NE(error_of(o).find("multiplicative"), std::string::npos);
  o = AttentionOptions{};
  o.max_targets = 0;
  EXPECT_NE(error_of(o).find("max_targets"), std::string::npos);
  o = AttentionOptions{};
  o.growth_max_m = -1;
  EXPECT_NE(error_of(o).find("growth_max_m"), std::string::npos);
  EXPECT_TRUE(AttentionOptions{}.IsValid(nullptr));
}

}  // namespace
}  // namespace saccade
