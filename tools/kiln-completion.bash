# bash completion for kiln (installed as share/bash-completion/completions/kiln).
# Options come from 'kiln COMMAND --help' itself, so the completion never falls behind the binary.
_kiln() {
    local cur=${COMP_WORDS[COMP_CWORD]}
    local commands="render info crosscheck bench tools --help --version"
    if ((COMP_CWORD == 1)); then
        mapfile -t COMPREPLY < <(compgen -W "$commands" -- "$cur")
        return
    fi
    local command=${COMP_WORDS[1]}
    if [[ $cur == -* ]]; then
        local options
        options=$("${COMP_WORDS[0]}" "$command" --help 2>/dev/null | grep -o -- '--[a-z][a-z0-9-]*' | sort -u)
        mapfile -t COMPREPLY < <(compgen -W "$options" -- "$cur")
        return
    fi
    mapfile -t COMPREPLY < <(compgen -f -- "$cur")
}
complete -o filenames -F _kiln kiln
