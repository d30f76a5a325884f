// The command line as CLI11 parses it: `lever --help` and `lever CMD --help` are complete and are
// what docs/cli.md shows, word for word; an unknown command or option, a missing positional and a
// value its check refuses exit 2 with one line naming the command.
#include <catch2/catch.hpp>

#include <algorithm>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <lever/harness/models.hpp>
#include "run_lever.hpp"

namespace lever::test {

namespace {

const std::vector<std::string> kCommands = {"model", "check",       "forward", "simulate",
                                            "diff",  "derivatives", "identify"};

// docs/cli.md holds `text` as one fenced block, whole.
bool documented(const std::string& doc, const std::string& text) {
  return doc.find("```\n" + text + "```\n") != std::string::npos;
}

int lines(const std::string& text) {
  return static_cast<int>(std::count(text.begin(), text.end(), '\n'));
}

}  // namespace

TEST_CASE("cli: lever --help lists every command, and docs/cli.md shows it", "[help]") {
  const std::string doc = read_text(model_path("docs/cli.md"));
  const Run help = run_lever("--help");
  CHECK(help.status == 0);
  for (const std::string& command : kCommands) {
    CHECK(help.out.find("\n  " + command + " ") != std::string::npos);
  }
  CHECK(documented(doc, help.out));

  const Run version = run_lever("--version");
  CHECK(version.status == 0);
  CHECK(version.out.rfind("lever ", 0) == 0);
}

TEST_CASE("cli: every command's --help, word for word in docs/cli.md", "[help]") {
  const std::string doc = read_text(model_path("docs/cli.md"));
  for (const std::string& command : kCommands) {
    INFO("lever " << command << " --help");
    const Run help = run_lever(command + " --help");
    CHECK(help.status == 0);
    if (command == "diff" && help.out.find("--states") == std::string::npos) {
      WARN("lever diff was built without MuJoCo 2.2.2: its help is not compared");
      continue;
    }
    CHECK(help.out.find("Usage: lever " + command + " [OPTIONS]") != std::string::npos);
    CHECK(help.out.find("Exit status:") != std::string::npos);
    CHECK(documented(doc, help.out));
    CHECK(run_lever(command + " -h").out == help.out);
  }
}

TEST_CASE("cli: usage errors exit 2 with one line naming the command", "[help]") {
  const std::string arm2 = quoted(model_path("models/arm2.xml"));
  struct Case {
    std::string args, starts;
  };
  const std::vector<Case> cases = {
      {"nosuch", "lever: unknown command 'nosuch'"},
      {"forward " + arm2 + " --no-such-option", "lever forward: "},
      {"forward", "lever forward: MODEL is required"},
      {"forward " + arm2 + " --qpos", "lever forward: --qpos"},
      {"forward " + arm2 + " --qpos 0.1,x", "lever forward: --qpos: 'x' is not a number"},
      {"forward " + arm2 + " --json=yes", "lever forward: "},
      {"simulate " + arm2 + " --steps 1.5", "lever simulate: --steps: '1.5' is not a whole number"},
      {"simulate " + arm2 + " --steps 2 --duration 1",
       "lever simulate: --steps excludes --duration"},
      {"simulate " + arm2 + " --ctrl 0,0 --torque 0,0", "lever simulate: --ctrl excludes --torque"},
      {"simulate " + arm2 + " --plot ''", "lever simulate: --plot: needs a name"},
      {"identify " + arm2, "lever identify: DATA.csv is required"},
      {"model", "lever model: expects one MODEL (or --schema)"},
      {"check " + arm2 + " " + arm2, "lever check: "},
  };
  for (const Case& c : cases) {
    INFO("lever " << c.args);
    const Run run = run_lever(c.args, true);  // stderr: nothing goes to stdout
    CHECK(run.status == 2);
    CHECK(run.out.rfind(c.starts, 0) == 0);
    CHECK(lines(run.out) == 1);
  }
  // a value that looks like an option is taken as the value it must be
  const Run negative = run_lever("forward " + arm2 + " --qpos -0.5,-1e-3 --json");
  CHECK(negative.status == 0);
  CHECK(negative.out.find("\"qpos\":[-0.5,-0.001]") != std::string::npos);
  // given twice, the last value counts
  const Run twice = run_lever("forward " + arm2 + " --qpos 1,1 --qpos=0.25,0.5 --json");
  CHECK(twice.out.find("\"qpos\":[0.25,0.5]") != std::string::npos);
}

}  // namespace lever::test
