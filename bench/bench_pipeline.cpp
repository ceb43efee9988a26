// Times core::Pipeline, single-threaded, on sweeps stored as simple binary files:
//   int64 rows, int64 cols, then echo 1 and echo 2, each rows*cols x 4 float32 (x y z intensity;
//   NaN x for no return). Usage: bench_pipeline [--repeats R] [--warmup W] [--budget S] FILE...
// --budget: stop a file's measured runs early once they took S seconds (at least 5 runs).
// Parameters: launch/rotating_hokuyo_params.yaml (outlier radius 0.2 m, 5 neighbours) for every file.
// Prints one JSON line per file: per-stage and total median / p95 seconds per sweep, beams per
// second (from the median total), and the process's peak RSS (VmHWM) after that file.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "ohm_mirror_detector3d/core/pipeline.h"

namespace core = ohm_mirror_detector3d::core;

namespace
{
core::Sweep readSweep(const std::string& path)
{
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw std::runtime_error("cannot open " + path);
  std::int64_t dims[2];
  in.read(reinterpret_cast<char*>(dims), sizeof(dims));
  if (!in || dims[0] < 0 || dims[1] < 0)
    throw std::runtime_error("bad header in " + path);
  const std::size_t n = static_cast<std::size_t>(dims[0] * dims[1]);
  core::Sweep sweep;
  sweep.resize(static_cast<std::size_t>(dims[0]), static_cast<std::size_t>(dims[1]));
  sweep.has_intensity = true;
  std::vector<float> buffer(4 * n);
  for (core::EchoCloud& echo : sweep.echoes)
  {
    in.read(reinterpret_cast<char*>(buffer.data()), static_cast<std::streamsize>(buffer.size() * sizeof(float)));
    if (!in)
      throw std::runtime_error("short file " + path);
    for (std::size_t i = 0; i < n; ++i)
    {
      echo.points[i] = Eigen::Vector3f(buffer[4 * i], buffer[4 * i + 1], buffer[4 * i + 2]);
      echo.intensities[i] = buffer[4 * i + 3];
    }
  }
  sweep.computeRanges();
  return sweep;
}

core::Params hokuyoParams()
{
  core::Params p;
  p.min_range = 0.1;
  p.max_range = 30.0;
  p.outlier_radius = 0.2;
  p.outlier_min_neighbors = 5;
  p.echo_threshold = 0.05;
  p.plane_threshold = 0.05;
  p.min_object_points = 100;
  p.vision_cone_margin = 0.05;
  p.icp_max_distance = 0.1;
  p.icp_fitness_threshold = 0.005;
  p.icp_min_points = 30;
  p.icp_min_inlier_fraction = 0.5;
  return p;
}

// Nearest-rank percentile of a copy of the samples.
double percentile(std::vector<double> v, double q)
{
  if (v.empty())
    return 0.0;
  std::sort(v.begin(), v.end());
  std::size_t rank = static_cast<std::size_t>(q * static_cast<double>(v.size()) + 0.999999);
  rank = std::min(std::max<std::size_t>(rank, 1), v.size());
  return v[rank - 1];
}

double peakRssMb()
{
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind("VmHWM:", 0) == 0)
      return std::strtod(line.c_str() + 6, nullptr) / 1024.0;  // kB
  return -1.0;
}
}  // namespace

int main(int argc, char** argv)
{
  int repeats = 20;
  int warmup = 2;
  double budget = 0.0;  // 0: no limit
  std::vector<std::string> files;
  for (int i = 1; i < argc; ++i)
  {
    const std::string arg = argv[i];
    if (arg == "--repeats" && i + 1 < argc)
      repeats = std::max(1, std::atoi(argv[++i]));
    else if (arg == "--warmup" && i + 1 < argc)
      warmup = std::max(0, std::atoi(argv[++i]));
    else if (arg == "--budget" && i + 1 < argc)
      budget = std::atof(argv[++i]);
    else
      files.push_back(arg);
  }
  if (files.empty())
  {
    std::cerr << "usage: bench_pipeline [--repeats R] [--warmup W] [--budget S] FILE...\n";
    return 2;
  }
  try
  {
    for (const std::string& file : files)
    {
      const core::Sweep sweep = readSweep(file);
      core::Pipeline pipeline(hokuyoParams());
      for (int i = 0; i < warmup; ++i)
        pipeline.process(sweep);
      const char* names[] = { "range_gate",    "outlier_filter", "echo_comparison", "object_extraction",
                              "type_analysis", "cone_labelling", "cleaned_output",  "total" };
      std::vector<std::vector<double>> samples(8);
      std::size_t objects = 0, cleaned = 0;
      int runs = 0;
      double spent = 0.0;
      for (; runs < repeats && !(budget > 0.0 && runs >= 5 && spent > budget); ++runs)
      {
        const core::PipelineResult& r = pipeline.process(sweep);
        const core::StageTimes& t = r.times;
        const double values[] = { t.range_gate,    t.outlier_filter, t.echo_comparison, t.object_extraction,
                                  t.type_analysis, t.cone_labelling, t.cleaned_output,  t.total };
        for (int s = 0; s < 8; ++s)
          samples[s].push_back(values[s]);
        spent += t.total;
        objects = r.objects.size();
        cleaned = r.cleaned.size();
      }
      const double median_total = percentile(samples[7], 0.5);
      std::printf("{\"file\": \"%s\", \"rows\": %zu, \"cols\": %zu, \"beams\": %zu, \"repeats\": %d, "
                  "\"objects\": %zu, \"cleaned_points\": %zu, \"beams_per_s\": %.1f, \"peak_rss_mb\": %.1f, "
                  "\"stages\": {",
                  file.c_str(), sweep.rows, sweep.cols, sweep.beamCount(), runs, objects, cleaned,
                  median_total > 0 ? static_cast<double>(sweep.beamCount()) / median_total : 0.0, peakRssMb());
      for (int s = 0; s < 8; ++s)
        std::printf("%s\"%s\": {\"median_s\": %.6g, \"p95_s\": %.6g}", s ? ", " : "", names[s],
                    percentile(samples[s], 0.5), percentile(samples[s], 0.95));
      std::printf("}}\n");
      std::fflush(stdout);
    }
  }
  catch (const std::exception& e)
  {
    std::cerr << "bench_pipeline: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
