#include "app/map_command.h"

#include <fretsim/support/parameters.h>
#include <fretsim/support/progress.h>
#include <fretsim/support/run_control.h>
#include <fretsim/output/map_file.h>
#include <fretsim/scenes/figures.h>
#include <fretsim/scenes/scene.h>

#include <fretsim/fem/parallel_environment.h>

#include <mpi.h>
#include <omp.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <mutex>
#include <set>
#include <sstream>
#include <thread>

namespace fretsim::app
{
  namespace
  {
    namespace fs = std::filesystem;

    /// What a point's record keeps of its run's numbers (absent ones are NaN).
    const std::vector<std::string> &record_numbers()
    {
      static const std::vector<std::string> names{
        "risk_max",         "risk_max_converged",     "risk_max_error_estimate", "risk_max_x_m",
        "risk_max_y_m",     "risk_max_depth_m",       "tangential_force_amplitude_N", "peak_pressure_Pa",
        "von_mises_max_Pa", "yield_margin",           "slip_area_fraction_max",  "wall_time_s"};
      return names;
    }

    [[noreturn]] void reject_axis(const std::string &text, const std::string &problem)
    {
      throw InputError("(command line)", "--axis", "'" + text + "': " + problem);
    }

    std::string exact_text(double value)
    {
      char buffer[40];
      std::snprintf(buffer, sizeof buffer, "%.17g", value);
      return buffer;
    }

    // ---- Records across MPI ranks: length-prefixed fields, values in hex so
    // every bit survives.
    void put(std::string &out, const std::string &field) { out += std::to_string(field.size()) + ':' + field; }

    std::string take(const std::string &in, std::size_t &at)
    {
      const auto colon = in.find(':', at);
      const auto size  = std::stoul(in.substr(at, colon - at));
      std::string field = in.substr(colon + 1, size);
      at                = colon + 1 + size;
      return field;
    }

    std::string hex(double value)
    {
      char buffer[40];
      std::snprintf(buffer, sizeof buffer, "%a", value);
      return buffer;
    }

    std::string encode(const output::MapRecord &record)
    {
      std::string out;
      put(out, std::to_string(record.index));
      put(out, std::to_string(record.axis_values.size()));
      for (const double value : record.axis_values)
        put(out, hex(value));
      for (const auto *text : {&record.status, &record.message, &record.regime, &record.parameters})
        put(out, *text);
      put(out, std::to_string(record.numbers.size()));
      for (const auto &[name, value] : record.numbers)
        {
          put(out, name);
          put(out, hex(value));
        }
      return out;
    }

    output::MapRecord decode(const std::string &in)
    {
      output::MapRecord record;
      std::size_t       at = 0;
      record.index         = std::stol(take(in, at));
      const auto axes      = std::stoul(take(in, at));
      for (std::size_t k = 0; k < axes; ++k)
        record.axis_values.push_back(std::strtod(take(in, at).c_str(), nullptr));
      for (auto *text : {&record.status, &record.message, &record.regime, &record.parameters})
        *text = take(in, at);
      const auto numbers = std::stoul(take(in, at));
      for (std::size_t k = 0; k < numbers; ++k)
        {
          const std::string name = take(in, at);
          record.numbers[name]   = std::strtod(take(in, at).c_str(), nullptr);
        }
      return record;
    }

    /// The map as every rank sees it.
    struct MapDefinition
    {
      std::string                                      config_file, scene, definition, output_directory;
      std::vector<std::pair<std::string, std::string>> overrides; // the user's, then the points' own
      std::vector<MapAxis>                             axes;
      std::vector<std::vector<double>>                 values; // per axis
      bool                                             boundary = false; // bisect for D = 1

      long size() const
      {
        long n = 1;
        for (const auto &v : values)
          n *= static_cast<long>(v.size());
        return n;
      }
      /// The axis values of point `index`, the first axis fastest.
      std::vector<double> point(long index) const
      {
        std::vector<double> result;
        for (const auto &v : values)
          {
            result.push_back(v[index % static_cast<long>(v.size())]);
            index /= static_cast<long>(v.size());
          }
        return result;
      }
    };

    /// One scene run at the given axis values.
    /// `folder`: under points/, where a scene that writes files writes them.
    output::MapRecord evaluate(const MapDefinition &map, long index, const std::vector<double> &values,
                               const std::string &folder)
    {
      output::MapRecord record;
      record.index       = index;
      record.axis_values = values;
      try
        {
          auto overrides = map.overrides;
          for (std::size_t k = 0; k < map.axes.size(); ++k)
            overrides.emplace_back(map.axes[k].path, exact_text(values[k]));
          auto parameters   = scenes::load_parameters(map.config_file, overrides);
          record.parameters = parameters.to_prm();
          const auto scene  = scenes::make_scene(std::move(parameters));
          scenes::RunOptions options;
          options.output_directory = (fs::path(map.output_directory) / "points" / folder).string();
          options.plots            = false;
          options.progress         = false;
          options.files            = false;
          const scenes::RunReport report = scene->run(options);
          record.status                  = report.completed ? "ok" : "interrupted";
          for (const auto &name : record_numbers())
            if (const auto found = report.numbers.find(name); found != report.numbers.end())
              record.numbers[name] = found->second;
          if (const auto found = report.labels.find("regime"); found != report.labels.end())
            record.regime = found->second;
        }
      catch (const std::exception &error)
        {
          record.status  = "failed";
          record.message = error.what();
        }
      return record;
    }

    /// D where the map reads its risk: the converged value where the scene
    /// estimates it, else D_max.
    double risk_of(const output::MapRecord &record)
    {
      if (record.status != "ok")
        return std::numeric_limits<double>::quiet_NaN();
      for (const char *name : {"risk_max_converged", "risk_max"})
        if (const auto found = record.numbers.find(name); found != record.numbers.end() && std::isfinite(found->second))
          return found->second;
      return std::numeric_limits<double>::quiet_NaN();
    }

    struct Ranks
    {
      int rank = 0, size = 1;
      int on_node = 1; ///< ranks sharing this rank's machine
    };

    Ranks ranks()
    {
      Ranks r;
      if (!fem::ParallelEnvironment::active())
        return r;
      r.rank = static_cast<int>(fem::ParallelEnvironment::rank());
      r.size = static_cast<int>(fem::ParallelEnvironment::n_ranks());
      MPI_Comm node;
      MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, r.rank, MPI_INFO_NULL, &node);
      MPI_Comm_size(node, &r.on_node);
      MPI_Comm_free(&node);
      return r;
    }

    constexpr int tag_result = 1, tag_finished = 2;

    /// Runs tasks 0..n-1, task k on rank k % ranks, `jobs` at a time per rank
    /// in threads; `collect(payload)` sees every task's payload on rank 0, in
    /// this (the calling) thread, as they finish. Only this thread calls MPI.
    /// No new task starts once an interrupt is requested.
    void run_tasks(long n, int jobs, const std::function<std::string(long)> &work,
                   const std::function<void(const std::string &)> &collect)
    {
      const Ranks       r = ranks();
      std::vector<long> mine;
      for (long k = r.rank; k < n; k += r.size)
        mine.push_back(k);
      std::mutex              mutex;
      std::condition_variable ready;
      std::deque<std::string> finished;
      std::atomic<std::size_t> next{0};
      int                      running = std::max(1, std::min<int>(jobs, static_cast<int>(mine.size())));
      if (mine.empty())
        running = 0;
      std::vector<std::thread> threads;
      const int                thread_count = running;
      for (int t = 0; t < thread_count; ++t)
        threads.emplace_back([&, t] {
          // Each point on one core: the cores go to points in parallel, and a
          // point's result does not depend on how many threads its loops had
          // (sums split over threads round differently).
          omp_set_num_threads(1);
          for (;;)
            {
              const std::size_t i = next++;
              if (i >= mine.size() || interrupt_requested())
                break;
              std::string payload = work(mine[i]);
              const std::lock_guard<std::mutex> lock(mutex);
              finished.push_back(std::move(payload));
              ready.notify_one();
            }
          const std::lock_guard<std::mutex> lock(mutex);
          --running;
          ready.notify_one();
        });

      int  other_ranks_finished = 0;
      bool told_root            = false;
      for (;;)
        {
          std::deque<std::string> batch;
          bool                    local_done;
          {
            std::unique_lock<std::mutex> lock(mutex);
            ready.wait_for(lock, std::chrono::milliseconds(20), [&] { return !finished.empty() || running == 0; });
            batch.swap(finished);
            local_done = running == 0;
          }
          for (const auto &payload : batch)
            if (r.rank == 0)
              collect(payload);
            else
              MPI_Send(payload.data(), static_cast<int>(payload.size()), MPI_CHAR, 0, tag_result, MPI_COMM_WORLD);
          if (r.rank == 0 && r.size > 1)
            for (int flag = 1; flag;)
              {
                MPI_Status status;
                MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &status);
                if (!flag)
                  break;
                int count = 0;
                MPI_Get_count(&status, MPI_CHAR, &count);
                std::string payload(static_cast<std::size_t>(count), '\0');
                MPI_Recv(payload.data(), count, MPI_CHAR, status.MPI_SOURCE, status.MPI_TAG, MPI_COMM_WORLD,
                         MPI_STATUS_IGNORE);
                if (status.MPI_TAG == tag_finished)
                  ++other_ranks_finished;
                else
                  collect(payload);
              }
          if (!local_done)
            continue;
          if (r.rank != 0)
            {
              if (!told_root)
                MPI_Send(nullptr, 0, MPI_CHAR, 0, tag_finished, MPI_COMM_WORLD);
              told_root = true;
              break;
            }
          if (other_ranks_finished == r.size - 1)
            break;
        }
      for (auto &thread : threads)
        thread.join();
    }

    /// The same vector on every rank, as rank 0 has it.
    std::vector<long> broadcast(std::vector<long> values)
    {
      if (!fem::ParallelEnvironment::active())
        return values;
      long size = static_cast<long>(values.size());
      MPI_Bcast(&size, 1, MPI_LONG, 0, MPI_COMM_WORLD);
      values.resize(static_cast<std::size_t>(size));
      MPI_Bcast(values.data(), static_cast<int>(size), MPI_LONG, 0, MPI_COMM_WORLD);
      return values;
    }

    /// Where D - 1 changes sign along one line of the first axis.
    struct BoundaryLine
    {
      std::vector<double> others; ///< the other axes' values
      double              value = std::numeric_limits<double>::quiet_NaN(), low = value, high = value;
    };

    /// Bisection of D - 1 on the first axis between grid neighbours whose D
    /// lie on both sides of 1, to `tolerance` of the axis's range (in its
    /// logarithm for a log axis); the boundary is then interpolated linearly
    /// in the final bracket.
    BoundaryLine bisect_line(const MapDefinition &map, const std::map<long, output::MapRecord> &grid, long line,
                             double tolerance)
    {
      const MapAxis &axis  = map.axes[0];
      const long     n0    = static_cast<long>(map.values[0].size());
      BoundaryLine   result;
      const auto     first = map.point(line * n0);
      result.others.assign(first.begin() + 1, first.end());
      const auto to_t   = [&](double v) { return axis.logarithmic ? std::log(v) : v; };
      const auto from_t = [&](double t) { return axis.logarithmic ? std::exp(t) : t; };
      for (long i = 0; i + 1 < n0; ++i)
        {
          const auto a = grid.find(line * n0 + i), b = grid.find(line * n0 + i + 1);
          if (a == grid.end() || b == grid.end())
            continue;
          double fa = risk_of(a->second) - 1.0, fb = risk_of(b->second) - 1.0;
          if (!std::isfinite(fa) || !std::isfinite(fb) || (fa > 0.0) == (fb > 0.0))
            continue;
          double       ta = to_t(map.values[0][i]), tb = to_t(map.values[0][i + 1]);
          const double width = tolerance * std::abs(to_t(axis.to) - to_t(axis.from));
          int          step  = 0;
          while (std::abs(tb - ta) > width)
            {
              const double tm = 0.5 * (ta + tb);
              auto         values = first;
              values[0]         = from_t(tm);
              const double fm   = risk_of(evaluate(map, -1, values,
                                                         "boundary_" + std::to_string(line) + "_" +
                                                           std::to_string(++step))) -
                                  1.0;
              if (!std::isfinite(fm))
                break;
              if ((fm > 0.0) == (fa > 0.0))
                ta = tm, fa = fm;
              else
                tb = tm, fb = fm;
            }
          result.low   = from_t(std::min(ta, tb));
          result.high  = from_t(std::max(ta, tb));
          result.value = from_t(ta + (tb - ta) * fa / (fa - fb));
          break; // the first crossing along the line
        }
      return result;
    }

    std::string encode(const BoundaryLine &line, long index)
    {
      std::string out;
      put(out, std::to_string(index));
      for (const double v : {line.value, line.low, line.high})
        put(out, hex(v));
      put(out, std::to_string(line.others.size()));
      for (const double v : line.others)
        put(out, hex(v));
      return out;
    }

    std::pair<long, BoundaryLine> decode_line(const std::string &in)
    {
      std::size_t  at    = 0;
      const long   index = std::stol(take(in, at));
      BoundaryLine line;
      for (double *v : {&line.value, &line.low, &line.high})
        *v = std::strtod(take(in, at).c_str(), nullptr);
      const auto others = std::stoul(take(in, at));
      for (std::size_t k = 0; k < others; ++k)
        line.others.push_back(std::strtod(take(in, at).c_str(), nullptr));
      return {index, line};
    }

    void write_csv(const std::string &path, const MapDefinition &map, const std::map<long, output::MapRecord> &grid)
    {
      const std::string temporary = path + ".tmp";
      {
        std::ofstream out(temporary);
        out << "index";
        for (const auto &axis : map.axes)
          out << "," << axis.path;
        out << ",status,regime";
        for (const auto &name : record_numbers())
          out << "," << name;
        out << ",message\n";
        out.precision(10);
        for (const auto &[index, record] : grid)
          {
            out << index;
            for (const double value : record.axis_values)
              out << "," << value;
            out << "," << record.status << "," << record.regime;
            for (const auto &name : record_numbers())
              {
                const auto found = record.numbers.find(name);
                out << ",";
                if (found != record.numbers.end())
                  out << found->second;
                else
                  out << "nan";
              }
            // The message as one plain cell: readable by any CSV reader.
            std::string message = record.message;
            for (char &c : message)
              c = c == ',' ? ';' : c == '\n' || c == '"' ? ' ' : c;
            out << "," << message << "\n";
          }
        if (!out)
          throw std::runtime_error("cannot write '" + temporary + "'");
      }
      fs::rename(temporary, path);
    }

    MapDefinition define_map(const MapOptions &options)
    {
      MapDefinition map;
      map.config_file      = options.config_file;
      map.output_directory = options.output_directory;
      // The base parameters, with the file's own map where no axis is given.
      const auto base = scenes::load_parameters(options.config_file, options.overrides);
      std::vector<std::string> axes = options.axes;
      if (axes.empty() && base.get("Map/Axes") != "none")
        {
          std::stringstream listed(base.get("Map/Axes"));
          for (std::string text; std::getline(listed, text, ';');)
            if (text.find_first_not_of(" \t") != std::string::npos)
              axes.push_back(text.substr(text.find_first_not_of(" \t"),
                                         text.find_last_not_of(" \t") - text.find_first_not_of(" \t") + 1));
        }
      map.boundary = options.boundary || base.get_bool("Map/Boundary");
      if (axes.empty() || axes.size() > 3)
        throw InputError(options.axes.empty() ? options.config_file : "(command line)",
                         options.axes.empty() ? "Map/Axes" : "--axis",
                         "expected one to three axes (--axis, or 'Map/Axes' in the scene file), got " +
                           std::to_string(axes.size()));
      for (const auto &text : axes)
        {
          map.axes.push_back(MapAxis::parse(text));
          for (std::size_t k = 0; k + 1 < map.axes.size(); ++k)
            if (map.axes[k].path == map.axes.back().path)
              reject_axis(text, "the parameter is already an axis");
          map.values.push_back(map.axes.back().values());
        }
      // Every axis's end values on the base parameters: a bad path or value
      // stops the map before any point runs.
      map.scene = base.scene();
      map.overrides   = options.overrides;
      for (const auto &setting : scenes::map_point_settings(map.scene))
        map.overrides.push_back(setting);
      for (const auto &axis : map.axes)
        for (const double value : {axis.from, axis.to})
          {
            auto parameters = scenes::load_parameters(options.config_file, options.overrides);
            parameters.set(axis.path, exact_text(value), "--axis '" + axis.text() + "'");
          }
      std::ostringstream definition;
      definition << "scene " << map.scene << "\n";
      for (const auto &axis : map.axes)
        definition << "axis " << axis.text() << "\n";
      for (const auto &[path, value] : map.overrides)
        definition << "set " << path << "=" << value << "\n";
      definition << base.to_prm();
      map.definition = definition.str();
      return map;
    }

    int jobs_per_rank(const MapOptions &options, const std::string &scene, const Ranks &r)
    {
      if (!scenes::runs_in_threads(scene))
        return 1;
      if (options.jobs > 0)
        return options.jobs;
      const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
      return std::max(1, cores / r.on_node);
    }

    /// One `fretsim map` command, stage by stage (every rank runs each).
    class MapRun
    {
    public:
      explicit MapRun(const MapOptions &options)
        : options(options)
        , map(define_map(options))
      {}

      void open()
      {
        if (!fem::ParallelEnvironment::active() && (started_by_mpi_launcher() || map.scene != "concentrated"))
          mpi = std::make_unique<fem::ParallelEnvironment>();
        r    = ranks();
        root = r.rank == 0;
        OutputPolicy policy;
        policy.own_files   = {"map.h5", "map.h5.part", "map.csv", "map.csv.tmp", "map.png", "boundary.csv", "points/"};
        policy.force       = options.force;
        policy.resume_file = "map.h5";
        std::vector<long> done;
        if (root)
          {
            folder = std::make_unique<OutputFolder>(map.output_directory, policy);
            std::vector<std::string> axis_names;
            for (const auto &axis : map.axes)
              axis_names.push_back(axis.text());
            const std::string path = file_path("map.h5");
            try
              {
                file = std::make_unique<output::MapFile>(path, map.scene, map.definition, axis_names,
                                                         record_numbers());
              }
            catch (const output::MapFileMismatch &)
              {
                throw InputError("(command line)", "-o",
                                 "'" + path + "' holds another map (other scene, parameters or axes); expected "
                                 "the same command to continue it, or --force to start over");
              }
            for (const auto &record : file->records())
              done.push_back(record.index);
          }
        else
          OutputFolder::check(map.output_directory, policy);
        done = broadcast(done);
        already.insert(done.begin(), done.end());
        jobs = jobs_per_rank(options, map.scene, r);
      }

      void prepare_scene() const
      {
        scenes::make_scene(scenes::load_parameters(map.config_file, options.overrides))->prepare();
      }

      /// False if interrupted.
      bool run_points()
      {
        std::vector<long> pending;
        for (long index = 0; index < map.size(); ++index)
          if (!already.count(index))
            pending.push_back(index);
        if (options.max_points > 0 && static_cast<long>(pending.size()) > options.max_points)
          pending.resize(static_cast<std::size_t>(options.max_points));
        install_interrupt_handlers();
        if (root)
          std::cout << "map: " << map.size() << " points of scene " << map.scene << ", " << already.size()
                    << " already in map.h5, " << pending.size() << " to run on " << r.size << " rank(s) × "
                    << jobs << " thread(s)\n";
        Progress progress("map", static_cast<long>(pending.size()), options.progress && root, "point");
        long     collected = 0;
        run_tasks(
          static_cast<long>(pending.size()), jobs,
          [&](long k) {
            char folder[32];
            std::snprintf(folder, sizeof folder, "point_%06ld", pending[k]);
            return encode(evaluate(map, pending[k], map.point(pending[k]), folder));
          },
          [&](const std::string &payload) {
            const auto record = decode(payload);
            if (record.status != "interrupted")
              file->append(record);
            progress.update(++collected, std::numeric_limits<double>::quiet_NaN());
          });
        progress.finish();
        if (interrupt_requested())
          {
            if (root)
              std::cerr << "fretsim: map interrupted; map.h5 holds the points done, the same command continues it\n";
            return false;
          }
        if (root)
          for (const auto &record : file->records())
            grid[record.index] = record;
        complete = root ? static_cast<long>(grid.size()) : 0;
        if (fem::ParallelEnvironment::active())
          MPI_Bcast(&complete, 1, MPI_LONG, 0, MPI_COMM_WORLD);
        if (root && complete < map.size())
          std::cout << "map: " << complete << " of " << map.size()
                    << " points in map.h5; the same command continues the map\n";
        return true;
      }

      /// If asked for and every point is done; the lines are spread like the points.
      void locate_boundary()
      {
        if (!map.boundary || complete < map.size())
          return;
        // Every rank needs the grid's risks to bracket its lines: their bits.
        std::vector<long> bits;
        if (root)
          for (long index = 0; index < map.size(); ++index)
            {
              const double risk = risk_of(grid.at(index));
              long         raw;
              std::memcpy(&raw, &risk, sizeof raw);
              bits.push_back(raw);
            }
        bits = broadcast(bits);
        std::map<long, output::MapRecord> risks;
        for (long index = 0; index < static_cast<long>(bits.size()); ++index)
          {
            double risk;
            std::memcpy(&risk, &bits[index], sizeof risk);
            risks[index].status              = std::isfinite(risk) ? "ok" : "failed";
            risks[index].numbers["risk_max"] = risk;
          }
        const long lines = map.size() / static_cast<long>(map.values[0].size());
        boundary.assign(static_cast<std::size_t>(lines), BoundaryLine{});
        Progress line_progress("boundary", lines, options.progress && root, "line");
        long     lines_done = 0;
        run_tasks(
          lines, jobs,
          [&](long line) { return encode(bisect_line(map, risks, line, options.boundary_tolerance), line); },
          [&](const std::string &payload) {
            const auto [line, result] = decode_line(payload);
            boundary[line]            = result;
            line_progress.update(++lines_done, std::numeric_limits<double>::quiet_NaN());
          });
        line_progress.finish();
      }

      /// On rank 0: the files written.
      std::vector<std::string> write_outputs()
      {
        if (!root)
          return {};
        std::vector<std::string> written{file_path("map.h5"), file_path("map.csv")};
        write_csv(written.back(), map, grid);
        if (!boundary.empty())
          written.push_back(write_boundary());
        long failed = 0;
        for (const auto &[index, record] : grid)
          failed += record.status == "failed";
        if (failed > 0)
          std::cerr << "fretsim: warning: " << failed << " of " << grid.size()
                    << " points failed; map.csv gives each one's message\n";
        file.reset();
        if (options.plots)
          for (const auto &figure : scenes::run_plot_script("plot_map.py", {map.output_directory}))
            written.push_back(figure);
        return written;
      }

    private:
      std::string file_path(const std::string &name) const
      {
        return (fs::path(map.output_directory) / name).string();
      }

      /// boundary.csv and /boundary in map.h5.
      std::string write_boundary()
      {
        std::vector<std::vector<double>> others;
        std::vector<double>              value, low, high;
        const std::string                path = file_path("boundary.csv");
        std::ofstream                    out(path);
        out.precision(10);
        for (std::size_t k = 1; k < map.axes.size(); ++k)
          out << map.axes[k].path << ",";
        out << map.axes[0].path << " at D=1,bracket low,bracket high\n";
        for (const auto &line : boundary)
          {
            others.push_back(line.others);
            value.push_back(line.value);
            low.push_back(line.low);
            high.push_back(line.high);
            for (const double v : line.others)
              out << v << ",";
            out << line.value << "," << line.low << "," << line.high << "\n";
          }
        file->write_boundary(others, value, low, high);
        return path;
      }

      const MapOptions                         &options;
      MapDefinition                             map;
      std::unique_ptr<fem::ParallelEnvironment> mpi;
      Ranks                                     r;
      bool                                      root = true;
      int                                       jobs = 1;
      std::unique_ptr<OutputFolder>             folder;
      std::unique_ptr<output::MapFile>          file;
      std::set<long>                            already;
      std::map<long, output::MapRecord>         grid; // rank 0: every record, by index
      long                                      complete = 0;
      std::vector<BoundaryLine>                 boundary;
    };
  } // namespace

  MapAxis MapAxis::parse(const std::string &text)
  {
    MapAxis    axis;
    const auto equals = text.find('=');
    if (equals == std::string::npos || equals == 0)
      reject_axis(text, "expected 'Section/Name=FROM:TO:N' or 'Section/Name=FROM:TO:N:log'");
    axis.path = text.substr(0, equals);
    std::vector<std::string> parts;
    std::stringstream        rest(text.substr(equals + 1));
    for (std::string part; std::getline(rest, part, ':');)
      parts.push_back(part);
    if (parts.size() < 3 || parts.size() > 4 || (parts.size() == 4 && parts[3] != "log" && parts[3] != "lin"))
      reject_axis(text, "expected FROM:TO:N or FROM:TO:N:log after '='");
    const auto number = [&](const std::string &part, const char *what) {
      char        *end   = nullptr;
      const double value = std::strtod(part.c_str(), &end);
      if (part.empty() || *end != '\0' || !std::isfinite(value))
        reject_axis(text, std::string("expected a finite number for ") + what + ", got '" + part + "'");
      return value;
    };
    axis.from         = number(parts[0], "FROM");
    axis.to           = number(parts[1], "TO");
    const double n    = number(parts[2], "N");
    axis.logarithmic  = parts.size() == 4 && parts[3] == "log";
    if (n != std::floor(n) || n < 1 || n > 10000)
      reject_axis(text, "expected a whole number of points N from 1 to 10000, got '" + parts[2] + "'");
    axis.count = static_cast<int>(n);
    if (axis.logarithmic && (axis.from <= 0.0 || axis.to <= 0.0))
      reject_axis(text, "expected FROM > 0 and TO > 0 on a log axis");
    if (axis.count > 1 && axis.from == axis.to)
      reject_axis(text, "expected FROM != TO for more than one point");
    return axis;
  }

  std::vector<double> MapAxis::values() const
  {
    std::vector<double> result;
    for (int i = 0; i < count; ++i)
      {
        const double s = count == 1 ? 0.0 : double(i) / (count - 1);
        result.push_back(i == count - 1 ? to :
                         logarithmic    ? from * std::pow(to / from, s) :
                                          from + (to - from) * s);
      }
    return result;
  }

  std::string MapAxis::text() const
  {
    return path + "=" + exact_text(from) + ":" + exact_text(to) + ":" + std::to_string(count) +
           (logarithmic ? ":log" : "");
  }

  std::vector<std::string> run_map_command(const MapOptions &options)
  {
    // 1. The map's definition, checked in full before anything is written.
    MapRun map(options);
    // 2. MPI (under mpirun, or for models every point shares), the output
    //    folder and map.h5: a new map, or the same map continued.
    map.open();
    // 3. What every point shares, built once.
    map.prepare_scene();
    // 4. The points not yet in map.h5, over ranks and threads.
    if (!map.run_points())
      return {};
    // 5. The D = 1 boundary along each line of the first axis.
    map.locate_boundary();
    // 6. map.csv, boundary.csv and map.png.
    return map.write_outputs();
  }
} // namespace fretsim::app
