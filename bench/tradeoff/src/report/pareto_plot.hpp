// The Pareto plots' gnuplot script (pareto.gp) and data: error against cost, one curve per
// model/integrator (double) and per peer configuration through the dt values of a scene.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "report/results_view.hpp"

namespace stickslip::tradeoff::report {

// figures: (scene, PNG file name) in the order the report shows them; scenes without a curve get
// no figure.
void write_gnuplot(const Results& results, const std::string& plot_dir,
                   const std::vector<std::pair<std::string, std::string>>& figures);

}  // namespace stickslip::tradeoff::report
