// omnishadow: headless batch renderer for glTF scenes with shadowed point lights.
// This is the one place where errors become messages and exit statuses:
// 0 success, 2 bad input or usage, 1 any other failure.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <new>
#include <string>
#include <system_error>

#include "cli/batch_command.h"
#include "cli/devices_command.h"
#include "cli/diff_command.h"
#include "cli/info_command.h"
#include "cli/render_command.h"
#include "cli/report_merge.h"
#include "cli/shader_cache_folder.h"
#include "cli/verify_command.h"
#include "renderer/core/errors.h"
#include "renderer/core/message_text.h"

namespace {

void printError(const std::string& text) {
  std::fprintf(stderr, "omnishadow: %s\n", omnishadow::oneLineMessage(text).c_str());
}

// A path the user gave that the system refused: too long, missing folder, a loop of links.
bool isInputProblem(const std::error_code& code) {
  static const std::errc kInput[] = {
      std::errc::filename_too_long, std::errc::no_such_file_or_directory,
      std::errc::not_a_directory,   std::errc::too_many_symbolic_link_levels,
      std::errc::is_a_directory,    std::errc::invalid_argument};
  for (std::errc e : kInput)
    if (code == e) return true;
  return false;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"omnishadow: headless glTF renderer with omnidirectional point-light shadows"};
  app.set_version_flag("--version", "omnishadow 0.1.0");
  app.require_subcommand(1);
  omnishadow::cli::RenderOptions render;
  omnishadow::cli::InfoOptions info;
  omnishadow::cli::BatchOptions batch;
  omnishadow::cli::DiffCommandOptions diff;
  omnishadow::cli::VerifyOptions verify;
  omnishadow::cli::DevicesOptions devices;
  omnishadow::cli::ReportMergeOptions reportMerge;
  omnishadow::cli::addRenderCommand(app, render);
  omnishadow::cli::addInfoCommand(app, info);
  omnishadow::cli::addBatchCommand(app, batch);
  omnishadow::cli::addDiffCommand(app, diff);
  omnishadow::cli::addVerifyCommand(app, verify);
  omnishadow::cli::addDevicesCommand(app, devices);
  omnishadow::cli::addReportCommand(app, reportMerge);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    // The command the error belongs to (every command, including devices and report).
    std::string command = "render";
    for (const CLI::App* sub : app.get_subcommands()) command = sub->get_name();
    std::fprintf(stderr, "omnishadow: %s\nRun 'omnishadow --help' or 'omnishadow %s --help'.\n",
                 e.what(), command.c_str());
    return 2;
  }

  // Before any thread, and before EGL loads Mesa: the commands that open a GL context.
  if (app.got_subcommand("render") || app.got_subcommand("batch") || app.got_subcommand("verify") ||
      app.got_subcommand("devices")) {
    const auto shaderCache = omnishadow::cli::keepShaderCacheUsable();
    if (render.device.verbose || batch.device.verbose || verify.device.verbose)
      std::fprintf(stderr, "omnishadow: %s\n",
                   omnishadow::cli::describeShaderCacheFolder(shaderCache).c_str());
  }

  try {
    if (app.got_subcommand("render")) return omnishadow::cli::runRender(render);
    if (app.got_subcommand("info")) return omnishadow::cli::runInfo(info);
    if (app.got_subcommand("batch")) return omnishadow::cli::runBatch(batch);
    if (app.got_subcommand("devices")) return omnishadow::cli::runDevices(devices);
    if (app.got_subcommand("report")) return omnishadow::cli::runReportMerge(reportMerge);
    // 0 within the tolerances, 1 not; InputError (2) for unreadable or incomparable images.
    if (app.got_subcommand("diff")) return omnishadow::cli::runDiff(diff);
    // 0 within --max-error, 1 not. require_subcommand(1) leaves no other command.
    return omnishadow::cli::runVerify(verify);
  } catch (const omnishadow::InputError& e) {
    printError(e.what());
    return 2;
  } catch (const std::filesystem::filesystem_error& e) {
    // Worded by us: "filesystem error: cannot create directories: File name too long [...]".
    const std::string path = e.path1().empty() ? std::string() : e.path1().string() + ": ";
    printError(path + e.code().message());
    return isInputProblem(e.code()) ? 2 : 1;
  } catch (const std::bad_alloc&) {
    printError("out of memory (an input asks for more than this machine can give)");
    return 1;
  } catch (const std::exception& e) {
    printError(e.what());
    return 1;
  }
}
