// The CLI's live plots (--show): a gnuplot process fed through
// gnuplot-iostream (Debian libgnuplot-iostream-dev), the engine's own plot
// scripts drawn in a window that stays open after chatter ends, or on the
// terminal GNUPLOT_TERM names (docs/plots.md). gnuplot-iostream pulls in
// Boost.Iostreams and Boost.Filesystem: only src/cli/live_plot.cpp includes
// it (the target chatter_live_plot, linked by the `chatter` executable
// alone); this header does not.
#pragma once

#include <memory>
#include <ostream>
#include <string>

#include "chatter/io/plot.hpp"
#include "cli_common.hpp"

namespace chatter::cli {

/// One gnuplot process: every draw() defines the datablock $data from the
/// plot's data, then runs its script (after `reset`, so that a redraw starts
/// clean). Image files are not written here: the io layer renders those by
/// running gnuplot on a script file and checks its exit status, which
/// gnuplot-iostream's pipe does not report.
class LiveWindow final : public PlotWindow {
 public:
  /// Starts `gnuplot -persist` with the terminal of `show`. Standard output
  /// is flushed first (a text terminal prints after it).
  explicit LiveWindow(const ShowRequest& show);
  /// Closes the pipe and waits for gnuplot to draw what it was sent; a window
  /// stays open (-persist).
  ~LiveWindow() override;
  LiveWindow(const LiveWindow&) = delete;
  LiveWindow& operator=(const LiveWindow&) = delete;
  /// @throws InputError when gnuplot has gone (it could not open its terminal:
  /// the display's fault, exit 2).
  void draw(const std::string& data, const std::string& script) override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The line that says where the plot went ("showing the plot in a gnuplot qt
/// window ..."); nothing for a text terminal (the plot itself is the output).
void report_shown(std::ostream& info, const ShowRequest& show);

}  // namespace chatter::cli
