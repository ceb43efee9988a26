// Times core::Pipeline, single-threaded, on sweeps stored as simple binary files:
//   int64 rows, int64 cols, then echo 1 and echo 2, each rows*cols x 4 float32 (x y z intensity;
//   NaN x for no return).
// Usage: bench_pipeline [--repeats R] [--warmup W] [--budget S] [--baseline B] [--rss-sweeps M] FILE...
// --budget: stop a file's measured runs early once they took S seconds (at least 5 runs).
// --baseline: also time the PCL baseline (bench/pcl_baseline.h) B times per file (0: not).
// --rss-sweeps: instead of timing, run M sweeps of each file through one pipeline and report
//   the resident set (VmRSS) after 100 sweeps and after M.
// Parameters: launch/rotating_hokuyo_params.yaml (outlier radius 0.2 m, 5 neighbours) for every file.
// Prints one JSON line per file: per-stage and total median / p95 seconds per sweep, beams per
// second (from the median total), and the process's peak RSS (VmHWM) after that file.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "ohm_mirror_detector3d/core/pipeline.h"
#include "pcl_baseline.h"

namespace core = ohm_mirror_detector3d::core;

namespace
{
// The simulated sweeps are in the scanner's frame.
const core::SweepContext& sensorContext()
{
  static const core::SweepContext context;
  return context;
}

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
  sweep.computeRanges(sensorContext().sensorOrigin());
  return sweep;
}

// The pipeline's `threads` (--threads; 0: automatic, the machine's cores up to 4).
int g_threads = 0;

core::Params hokuyoParams()
{
  core::Params p;
  p.threads = g_threads;
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

// CPU time of this process [s], all its threads (the pipeline's workers too): unlike wall time,
// not stretched by other processes on the machine.
double processCpuSeconds()
{
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
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

// A field of /proc/self/status in MB (VmHWM: peak resident set, VmRSS: current).
double statusMb(const char* field)
{
  std::ifstream status("/proc/self/status");
  std::string line;
  const std::string prefix = std::string(field) + ":";
  while (std::getline(status, line))
    if (line.rfind(prefix, 0) == 0)
      return std::strtod(line.c_str() + prefix.size(), nullptr) / 1024.0;  // kB
  return -1.0;
}

double peakRssMb()
{
  return statusMb("VmHWM");
}

// kMapObjects map objects for the post-filter's run: the sweep's own (merged on its first pass)
// and vertical 0.8 x 1.5 m panes on a ring of 4 to 8 m around the sensor, facing it, mirrors and
// glass by turns, each seen once: every one may label the sweep.
constexpr std::size_t kMapObjects = 20;

void fillMap(core::Pipeline& pipeline, const core::Sweep& sweep, const core::SweepContext& context)
{
  pipeline.process(sweep, context);
  std::vector<core::ReflectiveObject> panes;
  const std::size_t wanted = kMapObjects - std::min(kMapObjects, pipeline.objectMap().objects().size());
  for (std::size_t k = 0; k < wanted; ++k)
  {
    const float azimuth = 2.0f * static_cast<float>(M_PI) * static_cast<float>(k) / static_cast<float>(wanted);
    const float distance = 4.0f + 4.0f * static_cast<float>(k % 5) / 4.0f;
    const Eigen::Vector3f towards(std::cos(azimuth), std::sin(azimuth), 0.0f);
    core::ReflectiveObject pane;
    pane.type = k % 2 == 0 ? core::ObjectType::mirror : core::ObjectType::glass;
    pane.centre = distance * towards + Eigen::Vector3f(0.0f, 0.0f, 0.5f);
    pane.plane << -towards, distance;
    pane.width_axis = Eigen::Vector3f::UnitZ().cross(-towards).normalized();
    pane.height_axis = Eigen::Vector3f::UnitZ();
    pane.width = 0.8f;
    pane.height = 1.5f;
    pane.footprint = 0.02f;
    panes.push_back(pane);
  }
  std::vector<std::uint32_t> ids;
  pipeline.objectMap().observe(panes, context.fixed_from_sweep, ids);
}

// Resident set after 100 sweeps and after `sweeps` through one pipeline: buffers are reused,
// so it must not grow.
void measureRss(const std::string& file, const core::Sweep& sweep, int sweeps)
{
  core::Pipeline pipeline(hokuyoParams());
  double after_100 = 0.0;
  const auto start = std::chrono::steady_clock::now();
  for (int i = 1; i <= sweeps; ++i)
  {
    pipeline.process(sweep, sensorContext());
    if (i == 100)
      after_100 = statusMb("VmRSS");
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double after_all = statusMb("VmRSS");
  std::printf("{\"file\": \"%s\", \"beams\": %zu, \"sweeps\": %d, \"rss_after_100_mb\": %.2f, "
              "\"rss_after_all_mb\": %.2f, \"growth_mb\": %.2f, \"seconds\": %.1f}\n",
              file.c_str(), sweep.beamCount(), sweeps, after_100, after_all, after_all - after_100, seconds);
  std::fflush(stdout);
}
}  // namespace

int main(int argc, char** argv)
{
  int repeats = 20;
  int warmup = 2;
  double budget = 0.0;  // 0: no limit
  int baseline_repeats = 0;
  int rss_sweeps = 0;
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
    else if (arg == "--baseline" && i + 1 < argc)
      baseline_repeats = std::max(0, std::atoi(argv[++i]));
    else if (arg == "--rss-sweeps" && i + 1 < argc)
      rss_sweeps = std::max(100, std::atoi(argv[++i]));
    else if (arg == "--threads" && i + 1 < argc)
      g_threads = std::max(0, std::atoi(argv[++i]));
    else
      files.push_back(arg);
  }
  if (files.empty())
  {
    std::cerr << "usage: bench_pipeline [--repeats R] [--warmup W] [--budget S] [--baseline B] [--rss-sweeps M] "
                 "[--threads T] "
                 "FILE...\n";
    return 2;
  }
  try
  {
    for (const std::string& file : files)
    {
      const core::Sweep sweep = readSweep(file);
      if (rss_sweeps > 0)
      {
        measureRss(file, sweep, rss_sweeps);
        continue;
      }
      core::Pipeline pipeline(hokuyoParams());
      for (int i = 0; i < warmup; ++i)
        pipeline.process(sweep, sensorContext());
      const char* names[] = { "range_gate",    "outlier_filter", "echo_comparison", "object_extraction",
                              "type_analysis", "cone_labelling", "cleaned_output",  "total" };
      std::vector<std::vector<double>> samples(8);
      std::size_t objects = 0, cleaned = 0;
      std::string types;
      std::vector<double> cpu;
      int runs = 0;
      double spent = 0.0;
      for (; runs < repeats && !(budget > 0.0 && runs >= 5 && spent > budget); ++runs)
      {
        const double cpu_start = processCpuSeconds();
        const core::PipelineResult& r = pipeline.process(sweep, sensorContext());
        cpu.push_back(processCpuSeconds() - cpu_start);
        const core::StageTimes& t = r.times;
        const double values[] = { t.range_gate,    t.outlier_filter, t.echo_comparison, t.object_extraction,
                                  t.type_analysis, t.cone_labelling, t.cleaned_output,  t.total };
        for (int s = 0; s < 8; ++s)
          samples[s].push_back(values[s]);
        spent += t.total;
        objects = r.objects.size();
        types.clear();
        for (const core::ReflectiveObject& object : r.objects)
          types += std::string(types.empty() ? "\"" : ", \"") + core::objectTypeName(object.type) + "\"";
        cleaned = r.cleaned.size();
      }
      const double median_total = percentile(samples[7], 0.5);
      std::printf("{\"file\": \"%s\", \"rows\": %zu, \"cols\": %zu, \"beams\": %zu, \"repeats\": %d, "
                  "\"objects\": %zu, \"types\": [%s], \"cleaned_points\": %zu, \"beams_per_s\": %.1f, \"cpu_median_s\": %.6g, \"peak_rss_mb\": %.1f, "
                  "\"stages\": {",
                  file.c_str(), sweep.rows, sweep.cols, sweep.beamCount(), runs, objects, types.c_str(), cleaned,
                  median_total > 0 ? static_cast<double>(sweep.beamCount()) / median_total : 0.0, percentile(cpu, 0.5),
                  peakRssMb());
      for (int s = 0; s < 8; ++s)
        std::printf("%s\"%s\": {\"median_s\": %.6g, \"p95_s\": %.6g}", s ? ", " : "", names[s],
                    percentile(samples[s], 0.5), percentile(samples[s], 0.95));
      std::printf("}");
      {
        // The same sweep with extent growth of mirrors too (grow_objects 1; the defaults grow
        // panes only): the object stages' time and the reflection chains' (max_reflections as in
        // hokuyoParams) beside the whole pipeline's, same repeats.
        core::Params grow_params = hokuyoParams();
        grow_params.grow_objects = 1;
        core::Pipeline growing(grow_params);
        for (int i = 0; i < warmup; ++i)
          growing.process(sweep, sensorContext());
        std::vector<double> stages, chains, both, totals;
        for (int run = 0; run < runs; ++run)
        {
          const core::PipelineResult& r = growing.process(sweep, sensorContext());
          stages.push_back(r.times.object_stages);
          chains.push_back(r.times.reflection_chains);
          both.push_back(r.times.object_stages + r.times.reflection_chains);
          totals.push_back(r.times.total);
        }
        std::printf(", \"growth\": {\"object_stages_median_s\": %.6g, \"object_stages_p95_s\": %.6g, "
                    "\"reflection_chains_median_s\": %.6g, \"growth_and_chains_median_s\": %.6g, "
                    "\"total_median_s\": %.6g}",
                    percentile(stages, 0.5), percentile(stages, 0.95), percentile(chains, 0.5), percentile(both, 0.5),
                    percentile(totals, 0.5));
      }
      {
        // The same sweep with the post-filter on (post_filter), in a fixed frame that is the
        // sweep's own, against a map of kMapObjects objects: the post-filter stage (merging,
        // the map objects back into the sweep) and the whole pipeline, beside the total without.
        core::Params map_params = hokuyoParams();
        map_params.post_filter = 1;
        core::Pipeline mapping(map_params);
        core::SweepContext placed = sensorContext();
        placed.has_fixed_pose = true;
        fillMap(mapping, sweep, placed);
        for (int i = 0; i < warmup; ++i)
          mapping.process(sweep, placed);
        std::vector<double> stages, labelling, totals;
        std::size_t labelling_objects = 0;
        for (int run = 0; run < runs; ++run)
        {
          const core::PipelineResult& r = mapping.process(sweep, placed);
          stages.push_back(r.times.object_stages);
          labelling.push_back(r.times.cone_labelling);
          totals.push_back(r.times.total);
          labelling_objects = r.objects.size();
        }
        std::printf(", \"post_filter\": {\"map_objects\": %zu, \"labelling_objects\": %zu, "
                    "\"object_stages_median_s\": %.6g, \"object_stages_p95_s\": %.6g, "
                    "\"cone_labelling_median_s\": %.6g, \"total_median_s\": %.6g}",
                    mapping.objectMap().objects().size(), labelling_objects, percentile(stages, 0.5),
                    percentile(stages, 0.95), percentile(labelling, 0.5), percentile(totals, 0.5));
      }
      if (baseline_repeats > 0)
      {
        // The PCL baseline (bench/pcl_baseline.h) on the same sweep, right after ours.
        const char* baseline_names[] = { "outlier_filter", "echo_comparison", "planes", "icp", "total" };
        std::vector<std::vector<double>> baseline(5);
        std::size_t planes = 0;
        for (int run = 0; run < baseline_repeats; ++run)
        {
          const BaselineTimes b = runPclBaseline(sweep, sensorContext().sensorOrigin(), hokuyoParams());
          const double values[] = { b.outlier_filter, b.echo_comparison, b.planes, b.icp, b.total };
          for (int s = 0; s < 5; ++s)
            baseline[s].push_back(values[s]);
          planes = b.planes_found;
        }
        const double baseline_total = percentile(baseline[4], 0.5);
        std::printf(", \"baseline\": {\"repeats\": %d, \"planes\": %zu, \"speedup\": %.2f, \"stages\": {",
                    baseline_repeats, planes, median_total > 0 ? baseline_total / median_total : 0.0);
        for (int s = 0; s < 5; ++s)
          std::printf("%s\"%s\": {\"median_s\": %.6g}", s ? ", " : "", baseline_names[s],
                      percentile(baseline[s], 0.5));
        std::printf("}, \"peak_rss_mb\": %.1f}", peakRssMb());
      }
      std::printf("}\n");
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
