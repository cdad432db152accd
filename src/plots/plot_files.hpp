// Internal to the io layer: the three files of a plot (image, gnuplot script,
// data beside it), the script's head (terminal, output, common style) and the
// all-or-nothing render, shared by the plots of the shop data, grinding and
// the other families written in that style (chatter/io/plot.hpp has the
// public pieces: check_plot_path, fixed_size_terminal, render_gnuplot_image).
#pragma once

#include <filesystem>
#include <sstream>
#include <string>

#include "chatter/io/plot.hpp"
#include "chatter/io/table_writer.hpp"

namespace chatter::plot_detail {

/// The image, its data (.dat) and its script (.gp) side by side.
struct Files {
  std::filesystem::path image, data, script;
};

/// @throws InputError when the image's extension is not .png, .svg or .pdf.
inline Files files_for(const std::filesystem::path& image) {
  check_plot_path(image);
  Files f{image, image, image};
  f.data.replace_extension(".dat");
  f.script.replace_extension(".gp");
  return f;
}

/// The head of a script: how to rerun it, the terminal and output, the
/// `data` variable, the common border and grid.
inline std::string terminal(const Files& f, const std::string& what) {
  const ImageFormat fmt = check_plot_path(f.image);
  std::ostringstream s;
  s << "# " << what << ", written by chatter " << version() << ".\n"
    << "# Reproduce or restyle: cd into this directory, edit, then run\n#   gnuplot " << f.script.filename().string()
    << "\n# It reads " << f.data.filename().string() << " and writes " << f.image.filename().string() << ".\n\n"
    << "fs = " << (fmt == ImageFormat::pdf ? 10 : 14) << "\n";
  s << fixed_size_terminal(fmt);
  s << "set output " << gnuplot_quote(f.image.filename().string()) << "\nset encoding utf8\n"
    << "set datafile missing '?'\ndata = " << gnuplot_quote(f.data.filename().string()) << "\n"
    << "set border lw 1 lc rgb '#404040'\nset grid back lw 1 lc rgb '#d0d0d0'\n";
  return s.str();
}

/// Writes data and script (all or nothing), then runs gnuplot on the script.
inline PlotFiles render(const Files& f, const std::string& data, const std::string& script) {
  write_text_files({{f.data, data}, {f.script, script}});
  render_gnuplot_image(f.script, f.image);
  return {f.image, f.script, f.data};
}

}  // namespace chatter::plot_detail
