// Simulates one trajectory with the installed library and prints its status and duration.
#include <charconv>
#include <iostream>

#include "funnel/engine.hpp"
#include "funnel/geometry.hpp"
#include "funnel/params.hpp"

int main() {
  const funnel::Params params = funnel::default_params();
  const funnel::Trajectory t = funnel::simulate_release(params, funnel::make_geometry(params), 0.3);
  char buf[32];
  const auto end = std::to_chars(buf, buf + sizeof buf, t.duration).ptr;
  std::cout << "status " << funnel::to_string(t.status) << "\nduration " << std::string(buf, end) << "\n";
  return 0;
}
