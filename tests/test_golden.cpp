// Regression guard: a fixed set of trajectories must reproduce their recorded outputs, so that
// no optimisation changes results (tests/data/make_golden.sh regenerates the data).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "funnel/cone.hpp"
#include "funnel/engine.hpp"
#include "funnel/engine3d.hpp"
#include "funnel/grid.hpp"
#include "test_util.hpp"

namespace funnel {
namespace {

using test::near;

std::vector<std::map<std::string, std::string>> read_csv(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::vector<std::string> header;
  std::vector<std::map<std::string, std::string>> rows;
  auto split = [](const std::string& s) {
    std::vector<std::string> out;
    std::stringstream ss(s);
    std::string item;
    while (std::getline(ss, item, ',')) out.push_back(item);
    return out;
  };
  if (std::getline(in, line)) header = split(line);
  while (std::getline(in, line)) {
    const auto fields = split(line);
    std::map<std::string, std::string> row;
    for (std::size_t i = 0; i < header.size() && i < fields.size(); ++i) row[header[i]] = fields[i];
    rows.push_back(row);
  }
  return rows;
}

double num(const std::map<std::string, std::string>& row, const std::string& key) {
  return *parse_number(row.at(key));
}

/// The parameters of a golden row (the columns named as sweep parameters; absent ones: defaults).
Params row_params(const std::map<std::string, std::string>& row) {
  Params p = default_params();
  for (const std::string& name : sweep_parameter_names()) {
    std::string key = name;
    for (char& c : key) c = c == '-' ? '_' : c;
    if (row.count(key) != 0) {  // older files: defaults
      EXPECT_TRUE(set_parameter(p, name, num(row, key))) << name;
    }
  }
  EXPECT_FALSE(validate(p).has_value());
  return p;
}

/// The outputs a 2D and a 3D trajectory both have, against a golden row: the counts exactly, the
/// rest to `rel` relative (the energy loss also to `abs_loss` absolute).
template <class T>
void expect_row(const T& t, const std::map<std::string, std::string>& row, double rel, double abs_loss) {
  const std::string where = "theta " + row.at("theta") + " release " + row.at("release");
  EXPECT_EQ(to_string(t.status), row.at("status")) << where;
  EXPECT_EQ(t.collisions, static_cast<std::int64_t>(num(row, "collisions"))) << where;
  EXPECT_EQ(t.edge_collisions, static_cast<std::int64_t>(num(row, "edge_collisions"))) << where;
  EXPECT_EQ(t.contacts, static_cast<std::int64_t>(num(row, "contacts"))) << where;
  EXPECT_TRUE(near(t.duration, num(row, "duration"), rel)) << where;
  EXPECT_TRUE(near(t.impulse, num(row, "impulse"), rel)) << where;
  EXPECT_TRUE(near(t.normal_impulse, num(row, "normal_impulse"), rel)) << where;
  EXPECT_TRUE(near(t.energy_loss, num(row, "energy_loss"), rel, abs_loss)) << where;
  EXPECT_TRUE(near(t.contact_time, num(row, "contact_time"), rel)) << where;
}

TEST(Golden, RecordedTrajectoriesAreReproduced) {
  const auto rows = read_csv(FUNNEL_TEST_DATA_DIR "/golden_trajectories.csv");
  ASSERT_GE(rows.size(), 20u);
  for (const auto& row : rows) {
    const Params p = row_params(row);
    const Trajectory t = simulate_release(p, make_geometry(p), num(row, "release"));
    expect_row(t, row, 1e-12, 1e-14);
  }
}

TEST(Golden, Recorded3DTrajectoriesAreReproduced) {
  // Off-plane releases in the cone: integrated contacts on the face and the rim (their events
  // located on the dense output), rim collisions and spin. An optimisation of the 3D engine must
  // keep these; an event scanned with a stale frame moves them by 1e-3.
  const auto rows = read_csv(FUNNEL_TEST_DATA_DIR "/golden_3d.csv");
  ASSERT_GE(rows.size(), 12u);
  std::int64_t contacts = 0, edge_contacts = 0, edge_collisions = 0;
  for (const auto& row : rows) {
    Params p = row_params(row);
    p.release_w = num(row, "release_w");  // the 3D release's off-plane velocity and spin
    p.release_spin_x = num(row, "release_spin_x");
    p.release_spin_y = num(row, "release_spin_y");
    const Cone cone = make_cone(p);
    const Trajectory3 t = simulate_3d(p, cone, release_state_3d(p, cone, num(row, "release")));
    expect_row(t, row, 1e-10, 1e-13);
    const std::string where = "theta " + row.at("theta") + " release " + row.at("release");
    EXPECT_EQ(t.edge_contacts, static_cast<std::int64_t>(num(row, "edge_contacts"))) << where;
    EXPECT_TRUE(near(std::fabs(t.orbits), num(row, "orbits"), 1e-10)) << where;  // the CSV: |turns|
    contacts += t.contacts;
    edge_contacts += t.edge_contacts;
    edge_collisions += t.edge_collisions;
  }
  EXPECT_GE(contacts, 100);  // the cases still reach what they are there for
  EXPECT_GE(edge_contacts, 100);
  EXPECT_GE(edge_collisions, 20);
}

}  // namespace
}  // namespace funnel
