// Compiles every oscillator the library offers, for float and double (and the laws fixed point
// offers, for Fixed), with the core's own flags
// (-fno-exceptions -fno-rtti -Werror), so a header that stops building for one of them fails here.
#include "stickslip/core/fixed_point.hpp"
#include "stickslip/friction/laws.hpp"
#include "stickslip/metrics/batch_statistics.hpp"
#include "stickslip/metrics/running_statistics.hpp"
#include "stickslip/models/batch.hpp"
#include "stickslip/models/oscillator.hpp"

namespace stickslip {

template class Oscillator<double, NoFriction>;
template class Oscillator<double, SignumFriction>;
template class Oscillator<double, SmoothFriction<SmoothingLaw::atan>>;
template class Oscillator<double, SmoothFriction<SmoothingLaw::tanh>>;
template class Oscillator<double, SmoothFriction<SmoothingLaw::erf>>;
template class Oscillator<double, SmoothFriction<SmoothingLaw::rational>>;
template class Oscillator<double, CoulombStickSlip>;
template class Oscillator<double, StribeckStickSlip>;
template class Oscillator<float, NoFriction>;
template class Oscillator<float, SignumFriction>;
template class Oscillator<float, SmoothFriction<SmoothingLaw::atan>>;
template class Oscillator<float, SmoothFriction<SmoothingLaw::tanh>>;
template class Oscillator<float, SmoothFriction<SmoothingLaw::erf>>;
template class Oscillator<float, SmoothFriction<SmoothingLaw::rational>>;
template class Oscillator<float, CoulombStickSlip>;
template class Oscillator<float, StribeckStickSlip>;
template class Oscillator<Fixed, NoFriction>;
template class Oscillator<Fixed, SignumFriction>;
template class Oscillator<Fixed, SmoothFriction<SmoothingLaw::rational>>;
template class Oscillator<Fixed, CoulombStickSlip>;
template class RunningStatistics<double>;
template class RunningStatistics<float>;
template class StickSlipBatch<double, 8>;
template class StickSlipBatch<float, 8>;
template class BatchStatistics<double, 8>;
template class BatchStatistics<float, 8>;

}  // namespace stickslip

// Ride comfort (ISO 2631-1 weightings and figures).
#include "stickslip/metrics/ride_comfort.hpp"
namespace stickslip {
template class WeightingFilter<float>;
template class WeightingFilter<double>;
template class RideComfort<float>;
template class RideComfort<double>;
}  // namespace stickslip
