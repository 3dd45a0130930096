import Foundation

/// Every subcommand of `wayfinder`, in the order `--help` lists them.
enum Subcommands {
    static let all: [Subcommand.Type] = [
        ValidateMapCommand.self, PlacesCommand.self, ImportInavigateCommand.self,
        InspectCommand.self,
        ImportOccamCommand.self,
        ReplayCommand.self,
        EvalCommand.self,
        RenderCommand.self,
        BenchCommand.self,
        SimulateCommand.self,
        RangeCommand.self,
    ]
}

/// The `wayfinder --version` line: the tool's version and the file formats it reads and writes.
let wayfinderVersion = "wayfinder 0.9.0 (map format v1, session bundle format v1)"

func printTopLevelHelp() {
    var text = "wayfinder: accessible indoor wayfinding, replayed on the command line.\n\n"
    text += "Usage: wayfinder <command> [options]\n       wayfinder --help | --version\n\nCommands:\n"
    for c in Subcommands.all { text += "  \(c.name.padding(toLength: 18, withPad: " ", startingAt: 0))\(c.summary)\n" }
    text += "\n\(MapSpec.usageLine); the same names work for every command.\n"
    text += "Results go to stdout; warnings to stderr, and progress to stderr only when it is a terminal.\n"
    text += "Exit codes: 0 ok, 1 bad input (each command's --help says which), 2 usage (bad flags or arguments).\n"
    text += "Run 'wayfinder <command> --help' for a command's options.\n"
    print(text, terminator: "")
}

let argv = Array(CommandLine.arguments.dropFirst())
guard let name = argv.first, name != "--help", name != "-h" else {
    printTopLevelHelp()
    exit(argv.isEmpty ? 2 : 0)
}
if name == "--version" || name == "-V" {
    print(wayfinderVersion)
    exit(0)
}
guard let command = Subcommands.all.first(where: { $0.name == name }) else {
    FileHandle.standardError.write(Data("wayfinder: unknown command '\(name)' (see 'wayfinder --help')\n".utf8))
    exit(2)
}
var arguments = ArgumentList(Array(argv.dropFirst()))
if arguments.wantsHelp {
    print(command.usage)
    exit(0)
}
do {
    exit(try command.run(&arguments))
} catch let error as CLIError {
    FileHandle.standardError.write(Data("wayfinder \(name): \(error.description)\n".utf8))
    exit(error.exitCode)
} catch {
    FileHandle.standardError.write(Data("wayfinder \(name): \(error)\n".utf8))
    exit(1)
}
