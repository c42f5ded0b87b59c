// SPDX-License-Identifier: MIT
// The infocus executable: parses the command line and runs one subcommand. All work is in the
// library; this file only decides the exit status.
#include <malloc.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <new>
#include <string>

#include "commands.h"
#include "infocus_config.h"

namespace {

// Parses the command line and runs the command it names; returns the exit status.
int run(int argc, char** argv) {
    CLI::App app{
        "infocus: how sharp each part of a camera image is, how wide its blur is, and where the "
        "lens is focused.",
        "infocus"};
    app.set_version_flag("--version", std::string("infocus ") + INFOCUS_VERSION);
    app.require_subcommand(1);
    app.footer("Run 'infocus COMMAND --help' for a command's options.");

    const auto commands = infocus::cli::registerCommands(app);
    // CLI11 would only say "a subcommand is required" for a misspelt command: name it.
    std::string command;  // the command given, for the messages of its usage errors
    if (argc > 1 && argv[1][0] != '-') {
        bool known = false;
        std::string names;
        for (const auto& c : commands) {
            known = known || c.app->get_name() == argv[1];
            names += (names.empty() ? "" : ", ") + c.app->get_name();
        }
        if (!known) {
            std::cerr << "infocus: unknown command '" << argv[1] << "'; the commands are: " << names
                      << "\nRun 'infocus --help' for what each does.\n";
            return infocus::cli::kExitUsage;
        }
        command = argv[1];
    }
    // CLI11 would answer an unknown option before any command with "a subcommand is required".
    if (argc > 1 && argv[1][0] == '-') {
        const std::string arg = argv[1];
        if (arg != "-h" && arg != "--help" && arg != "--version") {
            std::cerr << "infocus: '" << arg
                      << "' is not an option; infocus takes --help, --version or a command first\n"
                         "Run 'infocus --help' for the commands.\n";
            return infocus::cli::kExitUsage;
        }
    }
    // An empty value ('--coc ""', '--focal=') would otherwise read as an option not given, or
    // as 0 for a number: the command would run on a default the user did not choose.
    for (int i = 2; i < argc; ++i) {
        const std::string arg = argv[i];
        const bool emptyAfter = arg.empty() && argv[i - 1][0] == '-';
        const bool emptyJoined = arg.size() > 2 && arg.rfind("--", 0) == 0 && arg.back() == '=';
        if (!arg.empty() && !emptyJoined) continue;
        const std::string label = command.empty() ? "infocus" : "infocus " + command;
        std::cerr << label << ": "
                  << (emptyAfter    ? "an empty argument follows " + std::string(argv[i - 1])
                      : emptyJoined ? "the value of " + arg.substr(0, arg.size() - 1) + " is empty"
                                    : std::string("an argument is empty"))
                  << "; give one, or leave the option out\nRun '" << label
                  << " --help' for the options.\n";
        return infocus::cli::kExitUsage;
    }
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        // CLI11's own message ("--output is required"), said by the command it concerns, with
        // where its options are listed.
        if (command.empty()) {
            app.exit(e);  // prints the message and the --help hint
        } else {
            std::cerr << "infocus " << command << ": " << e.what() << "\nRun 'infocus " << command
                      << " --help' for the options.\n";
        }
        return infocus::cli::kExitUsage;
    }
    for (const auto& c : commands) {
        if (!c.app->parsed()) continue;
        const int rc = c.run();
        // Output that could not be written (a full disk, /dev/full) is a failure, not a silent
        // success with an empty report. A command that failed has said why already.
        errno = 0;
        const bool flushed = std::fflush(stdout) == 0;
        if (rc != 0 || (flushed && !std::ferror(stdout) && std::cout.good())) return rc;
        const int e = errno;
        std::cerr << "infocus " << command << ": writing to standard output failed"
                  << (e ? std::string(": ") + std::strerror(e) : std::string())
                  << "; free disk space or write elsewhere\n";
        return infocus::cli::kExitFailure;
    }
    return infocus::cli::kExitUsage;
}

// Keeps freed blocks in the heap for the next frame. Every frame allocates and frees buffers of
// the same sizes (luma, previews, masks, scratch); by default glibc maps such blocks anew above a
// moving threshold and hands the heap's top back past twice it, so each frame faulted them in and
// zeroed them again, at a cost greater than measuring the frame. `live` still gives free pages
// back to the system every 10 s. All threads share one arena: with one for each thread (up to 8
// a core) the blocks a frame's short-lived workers freed stayed resident in arenas the next frame
// might not take, and a long `live` run's memory crept up in steps. Each thread allocates a few
// blocks a frame, too few for the shared lock to be contended.
void keepFreedBlocksForReuse() {
    mallopt(M_MMAP_THRESHOLD, 64 << 20);
    mallopt(M_TRIM_THRESHOLD, 128 << 20);
    mallopt(M_ARENA_MAX, 1);
}

}  // namespace

int main(int argc, char** argv) {
    keepFreedBlocksForReuse();
    // An exception that escapes a command (memory that runs out, a library that throws) is a
    // failure to report, not an abort that loses the reason and leaves a core file.
    const std::string label =
        argc > 1 && argv[1][0] != '-' ? "infocus " + std::string(argv[1]) : std::string("infocus");
    try {
        return run(argc, argv);
    } catch (const std::bad_alloc&) {
        std::cerr << label
                  << ": out of memory; free memory, or give a smaller input (size, regions, "
                     "frames)\n";
    } catch (const std::exception& e) {
        std::cerr << label << ": failed: " << e.what() << "\n";
    } catch (...) {
        std::cerr << label << ": failed with an unknown error\n";
    }
    return infocus::cli::kExitFailure;
}
