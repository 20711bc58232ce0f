# bash completion for brume (installed as share/bash-completion/completions/brume). The
# commands and each command's options come from the tool's own help text, so they follow
# the installed brume: `brume help` lists the commands, `brume help COMMAND` the options.
_brume()
{
    local cur=${COMP_WORDS[COMP_CWORD]} exe=${COMP_WORDS[0]} words
    if [ "$COMP_CWORD" -eq 1 ]; then
        words=$("$exe" help 2>/dev/null | awk '/^commands:/ {c = 1; next} /^$/ {c = 0} c {print $1}')
        mapfile -t COMPREPLY < <(compgen -W "$words --version" -- "$cur")
    elif [[ $cur == -* ]]; then
        words=$("$exe" help "${COMP_WORDS[1]}" 2>/dev/null | grep -o -e '--[a-z][a-z0-9-]*' | sort -u)
        mapfile -t COMPREPLY < <(compgen -W "$words" -- "$cur")
    else
        mapfile -t COMPREPLY < <(compgen -f -- "$cur")
    fi
}
complete -o filenames -o bashdefault -F _brume brume
