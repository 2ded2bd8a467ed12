// find_candidates rejects inputs it cannot search, with messages that name the offending
// edge, face or vertex.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "contact/broad_phase/find_candidates.hpp"

namespace dipc::contact {
namespace {

// Two triangles on 4 vertices, valid unless a test breaks it.
struct ValidInput {
  std::vector<double> x0 = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
  std::vector<double> x1 = x0;
  std::vector<std::int32_t> edges = {0, 1, 1, 2, 2, 0, 1, 3, 3, 2};
  std::vector<std::int32_t> faces = {0, 1, 2, 1, 3, 2};
  SurfaceView view() const {
    SurfaceView s;
    s.num_vertices = 4;
    s.x0 = x0.data();
    s.x1 = x1.data();
    s.num_edges = 5;
    s.edges = edges.data();
    s.num_faces = 2;
    s.faces = faces.data();
    return s;
  }
};

// Runs find_candidates and returns the BroadPhaseError message ("" when nothing is thrown).
std::string error_of(const SurfaceView& s, double inflation, Candidates* out, const CandidateFilter& filter = {}) {
  try {
    find_candidates(s, inflation, out, filter);
  } catch (const BroadPhaseError& e) {
    return e.what();
  }
  return "";
}

TEST(FindCandidatesErrors, ValidInputIsAccepted) {
  const ValidInput in;
  Candidates out;
  EXPECT_EQ(error_of(in.view(), 0.1, &out), "");
}

TEST(FindCandidatesErrors, BadInflationOrOutput) {
  const ValidInput in;
  Candidates out;
  EXPECT_NE(error_of(in.view(), -1e-9, &out).find("inflation"), std::string::npos);
  EXPECT_NE(error_of(in.view(), std::nan(""), &out).find("inflation"), std::string::npos);
  EXPECT_NE(error_of(in.view(), std::numeric_limits<double>::infinity(), &out).find("inflation"), std::string::npos);
  EXPECT_NE(error_of(in.view(), 0.1, nullptr).find("output is null"), std::string::npos);
}

TEST(FindCandidatesErrors, CountsAndNullArrays) {
  const ValidInput in;
  Candidates out;
  SurfaceView s = in.view();
  s.num_faces = -1;
  EXPECT_NE(error_of(s, 0.1, &out).find("negative count"), std::string::npos);
  s = in.view();
  s.x0 = nullptr;
  EXPECT_NE(error_of(s, 0.1, &out).find("x0 is null"), std::string::npos);
  s = in.view();
  s.edges = nullptr;
  EXPECT_NE(error_of(s, 0.1, &out).find("edges is null"), std::string::npos);
  s = in.view();
  s.faces = nullptr;
  EXPECT_NE(error_of(s, 0.1, &out).find("faces is null"), std::string::npos);
}

TEST(FindCandidatesErrors, VertexIdsOutOfRangeNameThePrimitive) {
  Candidates out;
  ValidInput in;
  in.faces[5] = 4;
  EXPECT_NE(error_of(in.view(), 0.1, &out).find("face 1 vertex 2 = 4 is outside [0, 4)"), std::string::npos);
  in = ValidInput{};
  in.edges[6] = -1;
  EXPECT_NE(error_of(in.view(), 0.1, &out).find("edge 3 vertex 0 = -1 is outside [0, 4)"), std::string::npos);
}

TEST(FindCandidatesErrors, NonFiniteCoordinatesNameTheVertex) {
  Candidates out;
  ValidInput in;
  in.x0[7] = std::nan("");
  EXPECT_NE(error_of(in.view(), 0.1, &out).find("vertex 2 has a non-finite x0 coordinate 1"), std::string::npos);
  in = ValidInput{};
  in.x1[11] = -std::numeric_limits<double>::infinity();
  EXPECT_NE(error_of(in.view(), 0.1, &out).find("vertex 3 has a non-finite x1 coordinate 2"), std::string::npos);
}

TEST(FindCandidatesErrors, GroupFilterNeedsGroups) {
  const ValidInput in;
  Candidates out;
  CandidateFilter filter;
  filter.allow_groups = [](int a, int b) { return a != b; };
  EXPECT_NE(error_of(in.view(), 0.1, &out, filter).find("vertex_group"), std::string::npos);
}

}  // namespace
}  // namespace dipc::contact
