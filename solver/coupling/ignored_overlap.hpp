// The overlap a surface contact ignores after its surface changed under a slave
// (coupling/surface_contact.hpp, docs/contact.md). A slave's signed distance s from the other
// body's surface moves, between two evaluations, by no more than the slave and the surface moved
// — unless the surface itself changed: an element eroded and exposed the faces behind it, a face
// turned into a node's view, the faces sharing a pinched corner gave its side the other way. Such
// a jump is not a motion: pushing the overlap it adds out would create energy (½ k δ² from
// nothing). So the overlap a jump adds is ignored — the force and the stored energy go on from
// where they were — and the ignored part only shrinks, as the slave comes out, never exceeding
// the overlap (LS-DYNA's "ignore initial penetration", applied at every change of the surface).
// Every motion further in is resisted from there on. A slave new to the surface (exposed by
// erosion) has its initial overlap ignored the same way. Verified by
// tests/coupling/ignored_overlap_test.cpp (the rule) and surface_contact_test.cpp (in a run).
#pragma once

#include <algorithm>
#include <cmath>

namespace sphfem {

// previous: s at the last evaluation, m (NaN: the slave is new to the surface); s: now, m;
// moved: how far the bodies' motion could have moved s since (a bound), m; expected: previous
// plus the change the motion made to first order, Δt ∇s · (v_slave − v_surface), m; overlap:
// the geometric overlap now (R − s), m; ignored: the overlap ignored until now, m. A change
// beyond `moved` is a change of the surface: the part of it the motion does not explain,
// expected − s, is ignored (the rest is the slave's motion, whose work the force must do).
// Returns the overlap to ignore now, in [0, max(overlap, 0)].
inline double ignored_overlap(double previous, double expected, double s, double moved,
                              double overlap, double ignored) {
  if (std::isnan(previous))
    ignored = overlap;
  else if (previous - s > moved)
    ignored += std::max(expected - s, 0.0);
  return std::clamp(ignored, 0.0, std::max(overlap, 0.0));
}

} // namespace sphfem
