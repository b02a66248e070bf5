#include "gcode/macro_loops.hpp"

#include <cmath>
#include <optional>
#include <sstream>
#include <vector>

#include <fmt/format.h>

#include "gcode/writer.hpp"

namespace beadtwin::gcode {
namespace {

// A block split around its Z word: `before` + Z<value> + `after`, or no Z word at all.
struct Split {
  std::string before, after;
  std::optional<double> z;
  int decimals = 0;  // digits after the point in the Z value as written
};

Split split_z(const std::string& line) {
  Split s;
  // Z words stand after a space in our programs ("G1 X1 Z0.2"); comments come last, in parentheses.
  const std::size_t comment = line.find('(');
  const std::size_t at = line.substr(0, comment).find(" Z");
  if (at == std::string::npos) {
    s.before = line;
    return s;
  }
  std::size_t end = at + 2;
  while (end < line.size() &&
         (std::isdigit(static_cast<unsigned char>(line[end])) || line[end] == '.' || line[end] == '-'))
    ++end;
  const std::string number = line.substr(at + 2, end - at - 2);
  try {
    s.z = std::stod(number);
  } catch (const std::exception&) {
    s.before = line;
    return s;
  }
  const std::size_t dot = number.find('.');
  s.decimals = dot == std::string::npos ? 0 : static_cast<int>(number.size() - dot - 1);
  s.before = line.substr(0, at);
  s.after = line.substr(end);
  return s;
}

struct Layer {
  std::string header;         // the "(LAYER ...)" comment
  std::vector<Split> blocks;  // the layer's other lines
};

// Whether `b` repeats `a` with every Z raised by `step` (within half a unit of the last decimal written).
bool repeats(const Layer& a, const Layer& b, double step) {
  if (a.blocks.size() != b.blocks.size()) return false;
  for (std::size_t i = 0; i < a.blocks.size(); ++i) {
    const Split &x = a.blocks[i], &y = b.blocks[i];
    if (x.before != y.before || x.after != y.after || x.z.has_value() != y.z.has_value()) return false;
    if (x.z && std::abs(*y.z - *x.z - step) > 0.5 * std::pow(10.0, -std::max(x.decimals, y.decimals)) + 1e-9)
      return false;
  }
  return true;
}

// The Z step from `a` to `b`: that of their first Z words.
std::optional<double> z_step(const Layer& a, const Layer& b) {
  for (std::size_t i = 0; i < a.blocks.size() && i < b.blocks.size(); ++i)
    if (a.blocks[i].z && b.blocks[i].z) return *b.blocks[i].z - *a.blocks[i].z;
  return std::nullopt;
}

// "(LAYER 3 SECTION ring Z 20 HEIGHT 5 TIME 23.4 S)" -> "(LAYER IN THE RUN SECTION ring HEIGHT 5)".
std::string run_layer_comment(const std::string& header) {
  const std::size_t section = header.find(" SECTION "), z = header.find(" Z "),
                    height = header.find(" HEIGHT ");
  if (section == std::string::npos || z == std::string::npos || height == std::string::npos)
    return "(LAYER IN THE RUN SECTION - HEIGHT 0)";
  const std::size_t height_end = header.find(' ', height + 8);
  return "(LAYER IN THE RUN" + header.substr(section, z - section) +
         header.substr(height, height_end - height) + ")";
}

}  // namespace

std::string loop_repeated_layers(const std::string& program, int min_layers) {
  // Lines before the first layer, the layers, and the lines after the last (the end of the program).
  std::vector<std::string> head, tail;
  std::vector<Layer> layers;
  std::istringstream in(program);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("(LAYER ", 0) == 0) {
      layers.push_back({line, {}});
    } else if (layers.empty()) {
      head.push_back(line);
    } else if (line == "M30" || line.find("(end of program)") != std::string::npos || !tail.empty()) {
      tail.push_back(line);
    } else {
      layers.back().blocks.push_back(split_z(line));
    }
  }
  std::string out;
  for (const std::string& l : head) out += l + '\n';
  for (std::size_t i = 0; i < layers.size();) {
    // The longest run from layer i on.
    std::size_t end = i + 1;
    std::optional<double> step;
    if (i + 1 < layers.size()) step = z_step(layers[i], layers[i + 1]);
    if (step && *step > 0)
      while (end < layers.size() && repeats(layers[end - 1], layers[end], *step)) ++end;
    const std::size_t count = end - i;
    if (!step || count < static_cast<std::size_t>(std::max(min_layers, 2))) {
      out += layers[i].header + '\n';
      for (const Split& b : layers[i].blocks)
        out += b.z ? b.before + " Z" + program_number(*b.z, b.decimals) + b.after + '\n' : b.before + '\n';
      ++i;
      continue;
    }
    // The run as one loop: #101 is the Z of the layer's first Z word; other Z words are offsets from it.
    const Layer& first = layers[i];
    int decimals = 0;
    double z0 = 0;
    bool have_z0 = false;
    for (const Split& b : first.blocks)
      if (b.z) {
        decimals = std::max(decimals, b.decimals);
        if (!have_z0) z0 = *b.z, have_z0 = true;
      }
    out += fmt::format("(LAYERS {} TO {}: ONE LAYER REPEATED {} TIMES, Z STEP {})\n",
                       first.header.substr(7, first.header.find(' ', 7) - 7),
                       layers[end - 1].header.substr(7, layers[end - 1].header.find(' ', 7) - 7), count,
                       program_number(*step, decimals));
    // The step from the run's first to its last layer, so rounding does not add up over the layers.
    double z_last = z0;
    for (const Split& b : layers[end - 1].blocks)
      if (b.z) {
        z_last = *b.z;
        break;
      }
    const std::string dz = program_number((z_last - z0) / static_cast<double>(count - 1), decimals + 4);
    out += "#100=0 (LAYER OF THE RUN)\n";
    out += fmt::format("WHILE [#100 LT {}] DO 1\n", count);
    out += fmt::format("#101={}+#100*{} (ITS Z)\n", program_number(z0, decimals), dz);
    // Each pass through the loop is a layer: its comment names the section and height, as the plain
    // program's layer comments do (a reader counts them).
    out += run_layer_comment(first.header) + '\n';
    for (const Split& b : first.blocks) {
      if (!b.z) {
        out += b.before + '\n';
        continue;
      }
      const double offset = *b.z - z0;
      const std::string z = std::abs(offset) < 0.5 * std::pow(10.0, -decimals)
                                ? "Z#101"
                                : fmt::format("Z[#101{}{}]", offset < 0 ? "-" : "+",
                                              program_number(std::abs(offset), decimals));
      out += b.before + " " + z + b.after + '\n';
    }
    out += "#100=#100+1\nEND 1\n";
    i = end;
  }
  for (const std::string& l : tail) out += l + '\n';
  return out;
}

}  // namespace beadtwin::gcode
