// The live plots of --show through gnuplot-iostream (src/cli/live_plot.hpp).
#include "live_plot.hpp"

#include <csignal>
#include <iostream>

#include <gnuplot-iostream.h>

#include "chatter/error.hpp"

namespace chatter::cli {

struct LiveWindow::Impl {
  Gnuplot gp{"gnuplot -persist"};
};

LiveWindow::LiveWindow(const ShowRequest& show) {
  // A gnuplot that cannot open its terminal exits: the next write must fail
  // with EPIPE (reported by draw), not kill chatter with SIGPIPE.
  std::signal(SIGPIPE, SIG_IGN);
  std::cout.flush();  // a text terminal prints after what chatter printed so far
  impl_ = std::make_unique<Impl>();
  impl_->gp << "set terminal " << show.terminal << "\n";
}

LiveWindow::~LiveWindow() = default;  // Gnuplot's destructor flushes and pcloses: gnuplot draws, then exits

void LiveWindow::draw(const std::string& data, const std::string& script) {
  Gnuplot& gp = impl_->gp;
  gp << "reset\n" << kLiveDataBlock << " << EOD\n" << data;
  if (!data.empty() && data.back() != '\n') gp << "\n";
  gp << "EOD\n" << script << std::flush;
  if (!gp.good())
    throw InputError("--show: gnuplot ended before the plot was drawn (its message is above; a window terminal "
                     "needs a working display: draw an image with --plot FILE instead)");
}

void report_shown(std::ostream& info, const ShowRequest& show) {
  if (!show.requested || show.text) return;
  info << "showing the plot in " << show.where << " (it stays open after chatter ends)\n";
}

}  // namespace chatter::cli
