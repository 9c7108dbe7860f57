# bash completion for kiln (installed as share/bash-completion/completions/kiln).
# Commands, subcommands, options and enumerated values come from 'kiln [COMMAND [SUB]] --help'
# itself, so the completion never falls behind the binary: options are the --names of the help,
# the values of an option are its "a|b|c" in the help (--aov's and --denoise-aovs' from their lists
# of layers); the names --display, --view and --look take come from the OCIO config, as
# 'kiln info --ocio' lists them (one per line, tab-separated: names may hold spaces).
_kiln_subcommands() {
    case $1 in
        bench) echo "accel plan accuracy" ;;
        farm) echo "submit status merge resubmit" ;;
        tools) echo "subdivide" ;;
        report) echo "cs184" ;;
        help) echo "render merge info crosscheck bench batch farm tools report denoise" ;;
    esac
}

# The config's names for --display, --view (of the --display given earlier on the line, else of
# every display) and --look, one per line.
_kiln_ocio_names() {
    local kind=$1 display= i
    for ((i = 1; i < COMP_CWORD - 1; ++i)); do
        [[ ${COMP_WORDS[i]} == --display ]] && display=${COMP_WORDS[i + 1]}
    done
    "${COMP_WORDS[0]}" info --ocio 2>/dev/null | awk -F'\t' -v kind="$kind" -v display="$display" '
        $1 == kind && kind != "view" { print $2 }
        $1 == "view" && kind == "view" && (display == "" || $2 == display) { print $3 }' | sort -u
}

_kiln() {
    local cur=${COMP_WORDS[COMP_CWORD]} prev=${COMP_WORDS[COMP_CWORD - 1]}
    local commands="render merge info crosscheck bench batch farm tools report denoise help --help --version"
    if ((COMP_CWORD == 1)); then
        mapfile -t COMPREPLY < <(compgen -W "$commands" -- "$cur")
        return
    fi
    local command=${COMP_WORDS[1]} subs
    subs=$(_kiln_subcommands "$command")
    if ((COMP_CWORD == 2)) && [[ -n $subs && $cur != -* ]]; then
        mapfile -t COMPREPLY < <(compgen -W "$subs" -- "$cur")
        return
    fi
    local asked=("$command")
    [[ -n $subs && $command != help && $command != farm ]] && asked+=("${COMP_WORDS[2]}")
    [[ $command == farm && ${COMP_WORDS[2]} != submit ]] && asked+=("${COMP_WORDS[2]}")
    [[ $command == farm && ${COMP_WORDS[2]} == submit ]] && asked=(render)
    local help
    help=$("${COMP_WORDS[0]}" "${asked[@]}" --help 2>/dev/null)
    [[ $command == farm && ${COMP_WORDS[2]} == submit ]] &&
        help+=$'\n'$("${COMP_WORDS[0]}" farm submit --help 2>/dev/null)
    if [[ $prev == --display || $prev == --view || $prev == --look ]]; then
        local names
        names=$(_kiln_ocio_names "${prev#--}")
        local IFS=$'\n'
        mapfile -t COMPREPLY < <(compgen -W "$names" -- "$cur")
        return
    fi
    if [[ $prev == --* ]]; then
        local values
        if [[ $prev == --aov ]]; then
            values=$(sed -n 's/.*comma-separated: \([^;]*\); or \([a-z, ]*\) .*/\1, \2/p' <<<"$help" | tr -d ',')
        elif [[ $prev == --denoise-aovs ]]; then
            values=$(sed -n 's/^ *--denoise-aovs LIST .*comma-separated: \([a-z_, ]*\)$/\1/p' <<<"$help" | tr -d ',')
        else
            values=$(sed -n "s/^ *\(-[a-zA-Z], \)\{0,1\}$prev \([^ ]*|[^ ]*\).*/\2/p" <<<"$help" | tr '|' ' ')
        fi
        if [[ -n $values ]]; then
            mapfile -t COMPREPLY < <(compgen -W "$values" -- "$cur")
            return
        fi
    fi
    if [[ $cur == -* ]]; then
        local options
        options=$(grep -o -- '--[a-z][a-z0-9-]*' <<<"$help" | sort -u)
        mapfile -t COMPREPLY < <(compgen -W "$options" -- "$cur")
        return
    fi
    mapfile -t COMPREPLY < <(compgen -f -- "$cur")
}
complete -o filenames -F _kiln kiln
