#!/usr/bin/env bash
# Checks, without a container engine, that the runtime stage of deploy/Dockerfile installs a
# Debian package for every shared library the built binaries load. Each library ldd reports is
# mapped to its package with dpkg; the package passes if the last stage's apt-get install list
# names it, if a named package pulls it in through Depends/Pre-Depends, or if debian:12 itself
# has it (the closure of the Essential and Priority: required packages). Dependencies are read
# from this machine's dpkg database, so it has to be Debian 12 with the build's packages.
#   dockerfile_runtime_test.sh BINARY... DOCKERFILE
set -euo pipefail

if (($# < 2)); then
    echo "usage: $(basename "$0") BINARY... DOCKERFILE" >&2
    exit 2
fi
binaries=("${@:1:$#-1}")
dockerfile=${!#}
for f in "${binaries[@]}" "$dockerfile"; do
    [[ -f $f ]] || { echo "no such file: $f" >&2; exit 2; }
done

# --- The packages the last stage installs ----------------------------------------------------

# Logical lines as docker reads them: backslash continuations joined, comment lines dropped
# (inside a continuation too).
logical=()
current=""
continuing=0
while IFS= read -r line || [[ -n $line ]]; do
    line=${line%$'\r'}
    if [[ $line =~ ^[[:space:]]*# ]] || { ((continuing)) && [[ $line =~ ^[[:space:]]*$ ]]; }; then
        continue
    fi
    if [[ $line =~ ^(.*)\\[[:space:]]*$ ]]; then
        current+="${BASH_REMATCH[1]} "
        continuing=1
        continue
    fi
    current+=$line
    continuing=0
    [[ $current =~ ^[[:space:]]*$ ]] || logical+=("$current")
    current=""
done < "$dockerfile"
[[ -z $current ]] || logical+=("$current")

last_from=-1
for i in "${!logical[@]}"; do
    read -r word _ <<< "${logical[$i]}"
    [[ ${word^^} == FROM ]] && last_from=$i
done
if ((last_from < 0)); then
    echo "FAIL: $dockerfile has no FROM"
    exit 1
fi

declare -A listed=()
stage_errors=0
for ((i = last_from + 1; i < ${#logical[@]}; i++)); do
    read -r word rest <<< "${logical[$i]}"
    case ${word^^} in
        ADD | ARG | CMD | COPY | ENTRYPOINT | ENV | EXPOSE | HEALTHCHECK | LABEL | MAINTAINER | \
            ONBUILD | SHELL | STOPSIGNAL | USER | VOLUME | WORKDIR) continue ;;
        RUN) ;;
        *)
            # A dropped trailing backslash leaves the rest of a RUN as lines docker rejects.
            read -ra words <<< "${logical[$i]}"
            printf 'FAIL: %s: not an instruction (a lost "\\" continuation?): %s\n' \
                "$dockerfile" "${words[*]}"
            stage_errors=$((stage_errors + 1))
            continue
            ;;
    esac
    commands=${rest//&&/$'\n'}
    commands=${commands//||/$'\n'}
    commands=${commands//;/$'\n'}
    commands=${commands//|/$'\n'}
    while IFS= read -r command; do
        read -ra words <<< "$command"
        state=start # start: before apt-get; verb: before install; packages: the list
        skip_value=0
        for w in "${words[@]}"; do
            if ((skip_value)); then skip_value=0; continue; fi
            case $state in
                start) [[ $w == apt-get || $w == */apt-get ]] && state=verb ;;
                verb)
                    case $w in
                        -o | -c | -t | --option | --config-file | --target-release) skip_value=1 ;;
                        -*) ;;
                        install) state=packages ;;
                        *) state=start ;; # another apt-get command
                    esac
                    ;;
                packages)
                    case $w in
                        -o | -c | -t | --option | --config-file | --target-release) skip_value=1 ;;
                        -*) ;;
                        *)
                            package=${w%%[=/]*} # pkg=version, pkg/release
                            listed[${package%%:*}]=1
                            ;;
                    esac
                    ;;
            esac
        done
    done <<< "$commands"
done
if ((${#listed[@]} == 0)); then
    echo "FAIL: the last stage of $dockerfile installs nothing with apt-get install"
    exit 1
fi

# --- What apt and the base image bring along -------------------------------------------------

# One dpkg-query for the whole database: each installed package's flags and dependencies, first
# alternative of each "a | b" (what apt installs when neither is there), versions dropped.
declare -A depends=() seeds=()
# shellcheck disable=SC2016 # dpkg-query's fields, not the shell's
fields='${db:Status-Abbrev}\t${Package}\t${Essential}\t${Priority}\t${Pre-Depends},${Depends}\n'
while IFS=$'\t' read -r status package essential priority deps; do
    [[ $status == ii* ]] || continue
    [[ $essential == yes ]] && seeds[$package]=Essential
    [[ $priority == required && -z ${seeds[$package]:-} ]] && seeds[$package]="Priority: required"
    names=""
    IFS=',' read -ra groups <<< "$deps"
    for group in "${groups[@]}"; do
        read -r name _ <<< "${group%%|*}"
        [[ -n $name ]] && names+=" ${name%%:*}"
    done
    depends[$package]="${depends[$package]:-}$names"
done < <(dpkg-query -W -f="$fields")

# Closure over Depends: reached[p] is the root that brings p in.
closure() { # closure ARRAY_NAME ROOT...
    local -n reached=$1
    shift
    local queue=("$@") root p d
    for root in "$@"; do reached["$root"]=$root; done
    while ((${#queue[@]})); do
        p=${queue[0]}
        queue=("${queue[@]:1}")
        for d in ${depends[$p]:-}; do
            if [[ -z ${reached[$d]:-} ]]; then
                reached["$d"]=${reached[$p]}
                queue+=("$d")
            fi
        done
    done
}
declare -A provided=() base=()
closure provided "${!listed[@]}"
closure base "${!seeds[@]}"

# --- The libraries the binaries load, and their packages -------------------------------------

declare -A needed_by=() # library path -> binaries
not_found=0
missing_re='^[[:space:]]*([^[:space:]]+)[[:space:]]+=>[[:space:]]+not found'
resolved_re='=>[[:space:]]+(/[^[:space:]]+)'
loader_re='^[[:space:]]*(/[^[:space:]]+)' # the dynamic loader: a path, no "=>"
for binary in "${binaries[@]}"; do
    name=$(basename "$binary")
    if ! out=$(ldd "$binary" 2>&1); then
        echo "FAIL: ldd $binary: $out"
        exit 1
    fi
    while IFS= read -r line; do
        if [[ $line =~ $missing_re ]]; then
            echo "FAIL: ${BASH_REMATCH[1]}: not found (needed by $name)"
            not_found=$((not_found + 1))
        elif [[ $line =~ $resolved_re || $line =~ $loader_re ]]; then
            needed_by[${BASH_REMATCH[1]}]+=" $name"
        fi # linux-vdso and the like: no file
    done <<< "$out"
done

# dpkg records one spelling of each file: the path ldd printed or its target, under /lib or
# under /usr/lib (merged /usr). Ask for all spellings at once; take the first that is known.
declare -A candidates=() owner=()
for library in "${!needed_by[@]}"; do
    list=""
    for p in "$library" "$(readlink -f "$library")"; do
        list+=" $p"
        case $p in
            /usr/lib*) list+=" ${p#/usr}" ;;
            /lib*) list+=" /usr$p" ;;
        esac
    done
    candidates[$library]=$list
done
while IFS= read -r line; do
    [[ $line == "diversion by "* || $line != *": /"* ]] && continue
    owner[${line#*: }]=${line%%: /*}
done < <(if ((${#candidates[@]})); then
             # shellcheck disable=SC2046 # one word per path
             dpkg-query -S $(printf '%s\n' "${candidates[@]}" | tr ' ' '\n' | sort -u) \
                 2>/dev/null || true
         fi)

declare -A package_libraries=() package_binaries=()
unowned=0
for library in "${!needed_by[@]}"; do
    packages=""
    for p in ${candidates[$library]}; do
        if [[ -n ${owner[$p]:-} ]]; then
            packages=${owner[$p]}
            break
        fi
    done
    if [[ -z $packages ]]; then
        echo "FAIL: $library (needed by${needed_by[$library]}) belongs to no Debian package"
        unowned=$((unowned + 1))
        continue
    fi
    # "libc6:amd64" or, for a file two packages share, "a:amd64, b:amd64": the first will do.
    package=${packages%%,*}
    package=${package%%:*}
    package_libraries[$package]+=" $library"
    package_binaries[$package]+="${needed_by[$library]}"
done

# --- Verdict ---------------------------------------------------------------------------------

missing=0
for package in $(printf '%s\n' "${!package_libraries[@]}" | sort); do
    if [[ -n ${listed[$package]:-} ]]; then
        reason="listed"
    elif [[ -n ${base[$package]:-} ]]; then
        seed=${base[$package]}
        reason="in debian:12 (${seeds[$seed]})"
        [[ $seed == "$package" ]] || reason="in debian:12 (through $seed, ${seeds[$seed]})"
    elif [[ -n ${provided[$package]:-} ]]; then
        reason="through ${provided[$package]}"
    else
        users=$(tr ' ' '\n' <<< "${package_binaries[$package]}" | sort -u | xargs)
        read -ra libraries <<< "$(tr ' ' '\n' <<< "${package_libraries[$package]}" | sort | xargs)"
        shown="${libraries[*]:0:3}"
        ((${#libraries[@]} <= 3)) || shown+=" and $((${#libraries[@]} - 3)) more"
        echo "MISSING $package: $shown (needed by $users)"
        missing=$((missing + 1))
        continue
    fi
    printf '  ok %-28s %s\n' "$package" "$reason"
done

problems=()
((missing == 0)) || problems+=("$missing package(s) missing")
((not_found == 0)) || problems+=("$not_found library(ies) not found")
((unowned == 0)) || problems+=("$unowned library(ies) from no package")
((stage_errors == 0)) || problems+=("$stage_errors line(s) not an instruction")
if ((${#problems[@]})); then
    (IFS=','; echo "FAIL: runtime stage of $dockerfile:${problems[*]/#/ }")
    exit 1
fi
echo "${#needed_by[@]} libraries of ${#binaries[@]} binaries from ${#package_libraries[@]}" \
     "packages, all provided by the runtime stage of $dockerfile"
