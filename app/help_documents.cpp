#include "help_documents.h"

#include <algorithm>
#include <cctype>
#include <map>
#include <sstream>

#include "commands.h"

namespace gm::cli {

namespace {

std::vector<std::string> lines(const std::string& text) {
    std::vector<std::string> out;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) out.push_back(line);
    return out;
}

// A line of text as troff shows it verbatim inside .nf: backslashes and hyphens escaped, a
// leading control character defused.
std::string troffLine(const std::string& line) {
    std::string out = line.empty() || (line[0] != '.' && line[0] != '\'') ? "" : "\\&";
    for (size_t k = 0; k < line.size(); ++k) {
        if (line[k] == '\\') out += "\\e";
        else if (line[k] == '-') out += "\\-";
        else if (line.compare(k, 3, "\u2014") == 0) out += "\\(em", k += 2;
        else out += line[k];
    }
    return out;
}

std::string troffBlock(const std::vector<std::string>& text) {
    std::string out = ".nf\n";
    for (const std::string& line : text) out += troffLine(line) + "\n";
    return out + ".fi\n";
}

// The main help without its title line (the man page's NAME) and the blank line after it.
std::vector<std::string> mainHelpBody() {
    std::vector<std::string> body = lines(mainHelp());
    body.erase(body.begin(), body.begin() + std::min<size_t>(2, body.size()));
    return body;
}

std::string description() {
    const std::string title = lines(mainHelp()).at(0);
    const size_t dash = title.find("\u2014");
    return dash == std::string::npos ? title : title.substr(dash + 4);
}

}  // namespace

std::vector<HelpOption> helpOptions(const std::string& help) {
    std::vector<HelpOption> options;
    for (const std::string& line : lines(help)) {
        if (line.compare(0, 3, "  -") != 0) continue;
        // The option names before the description, which starts after two spaces.
        const size_t end = line.find("  ", 2);
        const std::string names = line.substr(2, end == std::string::npos ? std::string::npos : end - 2);
        for (size_t k = 0; k < names.size(); ++k) {
            if (names[k] != '-' || (k > 0 && names[k - 1] != ' ')) continue;
            size_t e = k;
            while (e < names.size() && (std::isalnum(static_cast<unsigned char>(names[e])) || names[e] == '-')) ++e;
            HelpOption o{names.substr(k, e - k), e + 1 < names.size() && names[e] == ' ' && names[e + 1] != ' '};
            if (o.name.size() > 1 && std::none_of(options.begin(), options.end(), [&](const HelpOption& x) { return x.name == o.name; }))
                options.push_back(o);
            k = e;
        }
    }
    return options;
}

std::string manPage() {
    std::string page = ".TH GRADMESH 1 \"\" \"" + std::string(versionText()) + "\" \"User Commands\"\n";
    page += ".SH NAME\ngradmesh \\- " + troffLine(description()) + "\n";
    page += ".SH SYNOPSIS\n.B gradmesh\n.I command\n.RI [ options ]\n";
    page += ".SH DESCRIPTION\n" + troffBlock(mainHelpBody());
    page += ".SH COMMANDS\n";
    for (const Command& c : commands()) page += ".SS " + std::string(c.name) + "\n" + troffBlock(lines(c.help));
    page += ".SH EXIT STATUS\n0 on success, 1 when an input or output fails, 2 on a usage error.\n";
    page += ".SH SEE ALSO\nThe documentation in docs/ of the gradmesh sources: cli.md, batch.md, formats.md, limits.md.\n";
    return page;
}

namespace {

const char* const kImages = "png|jpg|jpeg|tif|tiff|exr";
const char* const kMeshes = "gmb|svg|svgz";
const char* const kWritten = "gmb|svg|svgz|eps|pdf|png|jpg|jpeg|tif|tiff|exr";

// The files each command reads (its positional arguments) and writes (-o).
struct CommandFiles {
    std::string inputs, outputs;
};

const std::map<std::string, CommandFiles>& commandFiles() {
    static const std::map<std::string, CommandFiles> files = {
        {"convert", {std::string(kImages) + "|" + kMeshes, kWritten}},
        {"render", {kMeshes, kImages}},
        {"info", {kMeshes, ""}},
        {"view", {kMeshes, "html|htm"}},
        {"compare", {kImages, ""}},
        {"batch", {std::string(kImages) + "|csv|jsonl", ""}},
        {"sample", {kWritten, ""}},
    };
    return files;
}

// "png|jpg" as a case-insensitive extglob alternative: "png|PNG|jpg|JPG".
std::string bothCases(const std::string& alternatives) {
    if (alternatives.empty()) return "";
    std::string upper = alternatives, out;
    std::transform(upper.begin(), upper.end(), upper.begin(), [](unsigned char c) { return std::toupper(c); });
    std::istringstream lower(alternatives), up(upper);
    for (std::string a, b; std::getline(lower, a, '|') && std::getline(up, b, '|');)
        out += (out.empty() ? "" : "|") + a + "|" + b;
    return out;
}

// A command's options as its help lists them; batch also takes convert's for each image, but
// those that name one file.
std::vector<HelpOption> commandOptions(const Command& c) {
    std::vector<HelpOption> options = helpOptions(c.help);
    if (std::string(c.name) != "batch") return options;
    for (const HelpOption& o : helpOptions(findCommand("convert")->help)) {
        const bool perImage = o.name == "-o" || o.name == "--output" || o.name == "--mask" ||
                              o.name == "--report" || o.name == "--output-dir" || o.name == "--to";
        if (!perImage && std::none_of(options.begin(), options.end(), [&](const HelpOption& x) { return x.name == o.name; }))
            options.push_back(o);
    }
    return options;
}

std::string completionCase(const Command& c) {
    std::string names, valued = " ";
    for (const HelpOption& o : commandOptions(c)) {
        names += (names.empty() ? "" : " ") + o.name;
        if (o.valued) valued += o.name + " ";
    }
    const CommandFiles& files = commandFiles().at(c.name);
    return "        " + std::string(c.name) + ")\n            options=\"" + names + "\"\n            valued=\"" +
           valued + "\"\n            inputs=\"" + bothCases(files.inputs) + "\"\n            outputs=\"" +
           bothCases(files.outputs) + "\";;\n";
}

const char* const kCompletionFunctions = R"script(# Files with one of the extensions $1 (extglob alternatives; "" any file), and directories.
_gradmesh_files() {
    local IFS=$'\n' restore
    restore=$(shopt -p extglob)
    shopt -s extglob
    if [[ -n $1 ]]; then
        COMPREPLY=($(compgen -f -X "!*.@($1)" -- "$cur") $(compgen -d -- "$cur"))
    else
        COMPREPLY=($(compgen -f -- "$cur"))
    fi
    eval "$restore"
    compopt -o filenames 2>/dev/null
    return 0
}

_gradmesh() {
    local cur=${COMP_WORDS[COMP_CWORD]} prev=${COMP_WORDS[COMP_CWORD-1]}
    local options valued inputs outputs
    COMPREPLY=()
    if ((COMP_CWORD == 1)); then
        COMPREPLY=($(compgen -W "@COMMANDS@ --help --version" -- "$cur"))
        return 0
    fi
    case ${COMP_WORDS[1]} in
@CASES@        *) return 0;;
    esac
    case $prev in
        --to) COMPREPLY=($(compgen -W "@FORMATS@" -- "$cur")); return 0;;
        --output-dir) COMPREPLY=($(compgen -d -- "$cur")); compopt -o filenames 2>/dev/null; return 0;;
        --mask|--image) _gradmesh_files "@IMAGES@"; return 0;;
        --report) _gradmesh_files "json|JSON|html|HTML"; return 0;;
        --log) _gradmesh_files "jsonl|JSONL"; return 0;;
        -o|--output) _gradmesh_files "$outputs"; return 0;;
    esac
    # The value of another option: nothing to offer.
    [[ $valued == *" $prev "* ]] && return 0
    if [[ $cur == -* ]]; then
        COMPREPLY=($(compgen -W "$options" -- "$cur"))
        return 0
    fi
    _gradmesh_files "$inputs"
}

complete -F _gradmesh gradmesh
)script";

void replace(std::string& text, const std::string& key, const std::string& value) {
    text.replace(text.find(key), key.size(), value);
}

}  // namespace

std::string bashCompletion() {
    std::string commandNames, cases;
    for (const Command& c : commands()) {
        commandNames += (commandNames.empty() ? "" : " ") + std::string(c.name);
        cases += completionCase(c);
    }
    std::string formats = kWritten;
    std::replace(formats.begin(), formats.end(), '|', ' ');
    std::string script = "# bash completion for gradmesh, generated from its help text at build time\n"
                         "# (app/help_documents.cpp).\n\n";
    script += kCompletionFunctions;
    replace(script, "@COMMANDS@", commandNames);
    replace(script, "@CASES@", cases);
    replace(script, "@FORMATS@", formats);
    replace(script, "@IMAGES@", bothCases(kImages));
    return script;
}

}  // namespace gm::cli
