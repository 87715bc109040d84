#include <fretsim/scenes/figures.h>

#include <fretsim/support/build_info.h>

#include <cstdio>
#include <filesystem>
#include <iostream>

namespace fretsim::scenes
{
  namespace
  {
    std::string shell_quote(const std::string &text)
    {
      std::string quoted = "'";
      for (const char c : text)
        quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
      return quoted + "'";
    }
  } // namespace

  std::vector<std::string> run_plot_script(const std::string &script_name, const std::vector<std::string> &arguments)
  {
    const std::string script = std::string(FRETSIM_SOURCE_DIR) + "/scripts/" + script_name;
    const std::string python = FRETSIM_PYTHON;
    if (python.empty() || !std::filesystem::exists(script))
      {
        std::cerr << "fretsim: warning: no figures (python3 with matplotlib and h5py, or " << script
                  << ", not found)\n";
        return {};
      }
    std::string command = shell_quote(python) + " " + shell_quote(script);
    for (const auto &argument : arguments)
      command += " " + shell_quote(argument);
    command += " 2>&1";
    std::vector<std::string> figures;
    std::string              messages;
    if (FILE *pipe = popen(command.c_str(), "r"))
      {
        char line[4096];
        while (std::fgets(line, sizeof line, pipe))
          {
            std::string text(line);
            while (!text.empty() && (text.back() == '\n' || text.back() == '\r'))
              text.pop_back();
            // The script prints the path of each PNG it wrote, one per line.
            if (text.size() > 4 && text.compare(text.size() - 4, 4, ".png") == 0 && std::filesystem::exists(text))
              figures.push_back(text);
            else
              messages += text + "\n";
          }
        if (pclose(pipe) != 0)
          std::cerr << "fretsim: warning: plotting failed:\n" << messages;
      }
    return figures;
  }

  std::vector<std::string> make_figures(const std::string &output_directory)
  {
    return run_plot_script("plot_results.py", {output_directory});
  }
} // namespace fretsim::scenes
