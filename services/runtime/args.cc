// Command lines of the hcosim tool and of every service.
#include "services/runtime/args.h"

#include <cmath>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include "services/runtime/participant.h"
#include "services/runtime/service.h"
#include "services/runtime/topics.h"

namespace hcosim::services::runtime {
namespace {

constexpr std::size_t kWidth = 100;     // synopsis lines wrap here
constexpr std::size_t kTextWidth = 80;  // descriptions wrap here
const std::string kIndent(8, ' ');      // under a command's synopsis

// `words` filled into lines of at most `width`, the first after `first`,
// the rest after `indent`.
std::string fill(const std::vector<std::string>& words, const std::string& first, const std::string& indent,
                 std::size_t width) {
  std::string out = first, line = first;
  bool empty = first.find_first_not_of(' ') == std::string::npos;
  for (const auto& w : words) {
    if (!empty && line.size() + 1 + w.size() > width) {
      out += "\n" + indent;
      line = indent;
      empty = true;
    }
    out += (empty ? "" : " ") + w;
    line += (empty ? "" : " ") + w;
    empty = false;
  }
  return out + "\n";
}

std::vector<std::string> words_of(const std::string& text) {
  std::vector<std::string> words;
  std::istringstream in(text);
  for (std::string w; in >> w;) words.push_back(w);
  return words;
}

// "FILE [--duration S] --out DIR [--quick]": one item per option, as defined.
std::vector<std::string> synopsis(const CLI::App* app) {
  std::vector<std::string> items;
  for (const CLI::Option* o : app->get_options()) {
    if (o == app->get_help_ptr()) continue;
    std::string item;
    if (o->get_positional()) {
      item = o->get_name(true, false);
    } else {
      item = "--" + o->get_lnames().front();
      if (!o->get_option_text().empty()) item += " " + o->get_option_text();
    }
    items.push_back(o->get_required() ? item : "[" + item + "]");
  }
  return items;
}

// The command's name from the root, as typed: "hcosim up".
std::string path_of(const CLI::App* app) {
  std::string path = app->get_name();
  for (const CLI::App* p = app->get_parent(); p; p = p->get_parent()) path = p->get_name() + " " + path;
  return path;
}

class Help : public CLI::Formatter {
 public:
  std::string make_usage(const CLI::App* app, std::string) const override {
    if (!app->get_subcommands({}).empty()) return "usage: " + path_of(app) + " COMMAND [ARGS]\n";
    return fill(synopsis(app), "usage: " + path_of(app), kIndent, kWidth);
  }

  // A command by its synopsis and what it does; one with commands of its
  // own ("security init") by each of those.
  std::string make_subcommand(const CLI::App* sub) const override {
    std::string out;
    for (const CLI::App* s : sub->get_subcommands({}))
      out += fill(synopsis(s), "  " + sub->get_name() + " " + s->get_name(), kIndent, kWidth) +
             fill(words_of(s->get_description()), kIndent, kIndent, kTextWidth);
    if (!out.empty()) return out;
    return fill(synopsis(sub), "  " + sub->get_name(), kIndent, kWidth) +
           fill(words_of(sub->get_description()), kIndent, kIndent, kTextWidth);
  }

  std::string make_description(const CLI::App* app) const override {
    return fill(words_of(app->get_description()), "", "", kTextWidth);
  }

  // The root's footer is about the whole tool: not repeated under each command.
  std::string make_footer(const CLI::App* app) const override {
    return app->get_parent() || app->get_footer().empty() ? "" : app->get_footer() + "\n";
  }

  std::string make_help(const CLI::App* app, std::string name, CLI::AppFormatMode mode) const override {
    if (app->get_subcommands({}).empty()) return CLI::Formatter::make_help(app, name, mode);
    // A program of commands: each by its synopsis, then the footer.
    std::string out = make_usage(app, name) + "\nCommands:\n";
    for (const CLI::App* sub : app->get_subcommands({}))
      if (!sub->get_group().empty()) out += make_subcommand(sub);
    const std::string footer = make_footer(app);
    return footer.empty() ? out : out + "\n" + footer;
  }
};

}  // namespace

CLI::Option* add_domain(CLI::App& app, int& domain) {
  return app.add_option("--domain", domain, "DDS domain id")
      ->option_text("D")
      ->envname("HCOSIM_DOMAIN")
      ->check(CLI::Range(0, adapters::kMaxDomain));
}

void add_dds(CLI::App& app, DdsOptions& o) {
  add_domain(app, o.domain);
  app.add_option("--security", o.security.dir, "join a secure domain with the files in DIR (docs/security.md)")
      ->option_text("DIR")
      ->envname("HCOSIM_SECURITY");
  app.add_option("--identity", o.security.identity, "identity in the secure domain")
      ->option_text("NAME")
      ->check(CLI::Validator([](std::string& s) { return s.empty() ? "needs a name" : ""; }, ""));
}

void add_topic_list(CLI::App& app, std::vector<std::string>& topics) {
  app.add_option("--topics", topics, "topics, comma-separated (default: every topic)")
      ->option_text("T1,T2")
      ->delimiter(',')
      ->check(topic_name());
}

CLI::Validator topic_name() {
  return CLI::Validator(
      [](std::string& t) {
        if (with_topic(t, [](auto) {})) return std::string();
        std::string known;
        for_each_topic([&](auto tag) {
          known += (known.empty() ? "" : ", ") + std::string(TopicOf<typename decltype(tag)::type>::name);
        });
        return "unknown topic '" + t + "' (known: " + known + ")";
      },
      "");
}

CLI::Validator within(double lo, double hi) {
  return CLI::Validator(
      [lo, hi](std::string& s) {
        std::size_t used = 0;
        double v = NAN;
        try {
          v = std::stod(s, &used);
        } catch (const std::exception&) {
        }
        if (used != s.size() || !std::isfinite(v) || v < lo || v > hi) {
          std::ostringstream m;
          m << "needs a number in [" << lo << ", " << hi << "], not '" << s << "'";
          return m.str();
        }
        return std::string();
      },
      "");
}

void use_hcosim_help(CLI::App& app) {
  app.formatter(std::make_shared<Help>());
  app.get_formatter()->column_width(24);
}

int run_command_line(CLI::App& app, int argc, const char* const* argv, const Command& chosen) {
  const std::string program = app.get_name();
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    std::cout << app.help();
    return 0;
  } catch (const CLI::ParseError& e) {
    // Point at the help of the command the error is in.
    std::string where = program;
    for (const CLI::App* a = &app; !a->get_subcommands().empty();)
      where += " " + (a = a->get_subcommands()[0])->get_name();
    std::cerr << program << ": " << e.what() << "\n(" << where << " --help shows the usage)\n";
    return 2;
  }
  if (!chosen) {
    std::cerr << app.help();
    return 2;
  }
  return guarded_main(program.c_str(), chosen);
}

}  // namespace hcosim::services::runtime
