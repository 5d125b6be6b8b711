#!/usr/bin/env python3
"""Cost of shader instrumentation on the demo renderer: frame times of `demo --bench` run
plainly, under the shim, and under the shim with GLBUDGET_INSTRUMENT=1, printed as a Markdown
table with ratios against the shim alone (same machine, same run of this script).
Also prints, for the best configuration, the static and measured instruction counts of every
program the demo drew (GLBUDGET_DUMP), so users can judge the static counts.

usage: instrumentation_cost.py BUILD_DIR [FRAMES]
"""
import json
import os
import re
import subprocess
import sys
import tempfile

ARGS = ['--scene', 'hall', '--detail', '0.05', '--width', '128', '--height', '72']


def bench(demo, frames, env):
    out = subprocess.run([demo, *ARGS, '--frames', str(frames), '--bench'], env={**os.environ, **env},
                         check=True, capture_output=True, text=True).stdout
    row = next(line for line in out.splitlines() if line.startswith('| hall |'))
    cells = [c.strip() for c in row.strip('|').split('|')]
    wall = lambda cell: float(re.match(r'[\d.]+', cell).group())
    return {'best wall ms': wall(cells[4]), 'best CPU ms': float(cells[5]),
            'cheapest wall ms': wall(cells[6]), 'cheapest CPU ms': float(cells[7])}


def static_vs_measured(demo, shim):
    with tempfile.TemporaryDirectory() as dump:
        subprocess.run([demo, *ARGS, '--frames', '6', '--config', '0,0,0,0,0,0'], check=True, capture_output=True,
                       env={**os.environ, 'LD_PRELOAD': shim, 'GLBUDGET_DUMP': dump, 'GLBUDGET_SENSOR': 'cpu'})
        rows = []
        for program in json.load(open(f'{dump}/index.json'))['programs']:
            for stage in json.load(open(f'{dump}/{program["file"]}'))['stages']:
                measured = stage.get('measured')
                if not measured or measured.get('instructions_per_invocation') is None or not stage.get('static'):
                    continue
                first_line = open(f'{dump}/shader-{stage["shader"]}.{stage["stage"]}.glsl').read().splitlines()[1:3]
                rows.append((program['hash'], stage['stage'], ' '.join(first_line)[:40], stage['static']['instructions'],
                             measured['instructions_per_invocation'], stage['static']['texture_calls'],
                             measured['texel_accesses_per_invocation']))
        return rows


def main():
    build = sys.argv[1]
    frames = int(sys.argv[2]) if len(sys.argv) > 2 else 20
    demo = f'{build}/testapps/demo/demo'
    shim = f'{build}/interpose/libglbudget.so'
    runs = {
        'plain': bench(demo, frames, {}),
        'shim': bench(demo, frames, {'LD_PRELOAD': shim, 'GLBUDGET_SENSOR': 'cpu'}),
        'shim + instrumentation': bench(demo, frames,
                                        {'LD_PRELOAD': shim, 'GLBUDGET_SENSOR': 'cpu', 'GLBUDGET_INSTRUMENT': '1'}),
    }
    keys = list(runs['plain'])
    print('| run | ' + ' | '.join(keys) + ' | best CPU / shim | cheapest CPU / shim |')
    print('|---|' + '---:|' * (len(keys) + 2))
    base = runs['shim']
    for name, r in runs.items():
        print(f'| {name} | ' + ' | '.join(f'{r[k]:.0f}' for k in keys) +
              f' | {r["best CPU ms"] / base["best CPU ms"]:.2f} | {r["cheapest CPU ms"] / base["cheapest CPU ms"]:.2f} |')
    print(f'\n(demo --bench, {frames} frames per row, 128x72 hall; CPU ms is where llvmpipe renders)\n')
    print('| program | stage | source | static instructions | measured / invocation | texture calls | texels / invocation |')
    print('|---|---|---|---:|---:|---:|---:|')
    for row in static_vs_measured(demo, shim):
        print('| {} | {} | {} | {} | {:.1f} | {} | {:.2f} |'.format(*row))


if __name__ == '__main__':
    main()
