// Flight audit of a whole line ensemble, shared by the corner and profile tests.
#pragma once

#include <cstdint>
#include <vector>

#include "funnel/audit.hpp"
#include "funnel/ensemble.hpp"
#include "funnel/funnel.hpp"

namespace funnel::test {

/// The audit of every free flight of n line releases in funnel f (rebuilt from each event log),
/// merged in sample order, and the number of sustained edge contacts they made.
struct EnsembleAudit {
  FlightAudit flights;
  std::int64_t edge_contacts = 0;
};

inline EnsembleAudit audit_line_ensemble(const Params& p, const Funnel& f, std::int64_t n) {
  std::vector<FlightAudit> audits(static_cast<std::size_t>(n));
  std::vector<std::int64_t> contacts(static_cast<std::size_t>(n));
#pragma omp parallel for schedule(dynamic, 16)
  for (std::int64_t k = 0; k < n; ++k) {
    const double x = release_fraction(ReleaseDist::Line, k, n);
    EventLog log;
    const Trajectory t = simulate_release(p, f, x, &log);
    audits[static_cast<std::size_t>(k)] = audit_flights(f, release_state(p, f, x), log.events);
    contacts[static_cast<std::size_t>(k)] = t.edge_contacts;
  }
  EnsembleAudit out;
  for (std::int64_t k = 0; k < n; ++k) {
    out.flights.merge(audits[static_cast<std::size_t>(k)]);
    out.edge_contacts += contacts[static_cast<std::size_t>(k)];
  }
  return out;
}

}  // namespace funnel::test
