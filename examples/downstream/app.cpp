// A downstream program built against an installed hedra (find_package(hedra)): builds an L
// prism, decomposes it into convex pieces, draws a scene with hidden lines and prints a
// summary that tests/install/ checks.
#include <hedra/hedra.h>

#include <fstream>
#include <iostream>

int main(int argc, char** argv) {
  using namespace hedra;
  const Body l = prism({{0, 0}, {4, 0}, {4, 1}, {1, 1}, {1, 3}, {0, 3}}, 0, 2);
  const Decomposition d = decompose(l);
  double volume = 0;
  for (const Body& piece : d.pieces) volume += piece.volume();

  Scene scene;
  scene.add("L", l);
  scene.add("box", box({5, 0, 0}, {6, 1, 1}));
  scene.camera = Camera::parallel({-1, -1, -1});
  const HlrResult lines = hidden_lines(scene);
  SvgStyle style;
  const std::string svg = hidden_lines_svg(lines, style);
  if (argc > 1) std::ofstream(argv[1]) << svg;

  std::cout << "hedra " << kVersion << "\n"
            << "convex " << convexity(l).convex << "\n"
            << "pieces " << d.pieces.size() << "\n"
            << "volume " << volume << "\n"
            << "visible " << lines.visible.size() << "\n"
            << "svg " << (svg.find("<svg") != std::string::npos) << "\n";
}
