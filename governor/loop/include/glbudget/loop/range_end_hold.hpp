#pragma once

#include <cstddef>
#include <map>

namespace glbudget::loop {

// Beyond the paper: the ends of a share's range (the best and the cheapest configuration) are
// measured once, early, and from then on predicted: the best is drawn only until the first
// selection, so from about frame 350 the model's 300-frame history holds none of its frames,
// and every refit predicts it from coefficients fitted where other levels were drawn. Most
// refits move it by little, and often rightly; some move it, and the budget with it, by more
// than the range is wide (the demo's Hall at 40 %: a refit at frame 519 moved the best's
// prediction for the same counts from 37.6 to 23.6 W while it drew 34.5 W, and the budget fell
// from 25.2 to 16.3 W; Valley at 60 %: both ends up by 11-19 W on a range 6 W wide, while it
// drew 20 W throughout).
//
// At each selection the governor predicts each end again with the coefficients and fragment
// scales of the last selection, at this frame's counts: the difference from its prediction now
// is the model's change alone, the counts being the same. A change of more than a quarter of
// the end's own power above idle, for an end no fit saw drawn, is taken for an extrapolation
// and carried back, so that the end moves only by how the counts changed, as the coefficients
// before the change see them. Smaller changes are the model learning and stand: on the loop
// tests' six-pass scene, whose model is of the scene's own family, they reach 1.9 W of the
// best's 33 W above idle and are right (carried back, they put the budget up to 1.5 W off,
// against 0.2 W). The scale is the end's own power rather than the range's width, which is
// near nothing where the levels save little (the loop tests' scene whose cheaper levels cost
// what the counts do not say: 1 W) and would take every refit for an extrapolation. Once a fit
// sees the end drawn again, its own prediction holds and nothing is carried.
class RangeEndHold {
 public:
  static constexpr double kImplausibleShare = 0.25;  // of the end's power above idle, at once

  // One end (by space index) at a selection: `change_w`, the model's change of its prediction
  // since the last selection at this frame's counts (NaN: not known); `seen`, a fit of the
  // model's saw it drawn; `above_idle_w`, its prediction before the change less P_m. True where
  // the change was carried back.
  bool observe(std::size_t end, double change_w, bool seen, double above_idle_w);
  // What is added to the end's prediction: the changes carried back so far.
  double carried_w(std::size_t end) const;
  void clear() { carried_w_.clear(); }
  // The top is this one now (it moves where estimates tie): what others carried goes.
  void keep_only(std::size_t top);

 private:
  std::map<std::size_t, double> carried_w_;
};

}  // namespace glbudget::loop
