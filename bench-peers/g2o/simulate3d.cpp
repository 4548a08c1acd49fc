// Writes a graph of g2o's 3D simulator (g2o::Simulator3D of libg2o_simulator):
// a robot on a grid with 3D odometry, and optionally a point sensor
// (VERTEX_TRACKXYZ, EDGE_SE3_TRACKXYZ) and a "GPS" pose prior (EDGE_SE3_PRIOR
// through a sensor offset). The simulator fixes the first pose, which g2o's
// save writes as a FIX line.
//
//   simulate3d OUTPUT [--steps N] [--landmarks N] [--world SIZE]
//                     [--points] [--gps] [--seed S]
//
// g2o ships an application for this (g2o/apps/g2o_simulator/g2o_simulator3d),
// but at the commit whose headers the g2opy wheel carries it declares a flag
// without dashes, which CLI11 rejects at start-up; this driver sets the same
// configuration directly. This file is this project's (bench-peers/g2o/
// simulate.sh builds it); it is not g2o code.
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <string>

#include "g2o/simulator/simulator3d_base.h"

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: simulate3d OUTPUT [--steps N] [--landmarks N] "
                 "[--world SIZE] [--points] [--gps] [--seed S]\n";
    return 2;
  }
  g2o::Simulator3D::Config config;
  config.hasOdom = true;
  config.simSteps = 100;
  config.nlandmarks = 1000;
  config.worldSize = 25.0;
  unsigned seed = 0;
  bool seeded = false;
  for (int i = 2; i < argc; ++i) {
    std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::cerr << a << " needs a value\n";
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--steps") config.simSteps = std::stoi(value());
    else if (a == "--landmarks") config.nlandmarks = std::stoi(value());
    else if (a == "--world") config.worldSize = std::stod(value());
    else if (a == "--points") config.hasPointSensor = true;
    else if (a == "--gps") config.hasGPS = true;
    else if (a == "--seed") { seed = std::stoul(value()); seeded = true; }
    else {
      std::cerr << "unknown option " << a << "\n";
      return 2;
    }
  }
  g2o::Simulator3D simulator(std::move(config));
  if (seeded) simulator.seed(seed);
  simulator.setup();
  simulator.simulate();
  std::ofstream out(argv[1]);
  simulator.world().graph().save(out);
  return out.good() ? 0 : 1;
}
