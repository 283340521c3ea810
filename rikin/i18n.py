"""The language of the words rikin prints in its tables: English, or Spanish for the
Spanish edition of the book.

Only what a table or a figure shows is translated: column headers ("branch", "joint", ...),
branch names ("front/up/no-flip" -> "delante/arriba/sin voltear") and the few phrases of
the solution figures' titles, buttons and legends (:func:`phrase`); the numbers are
formatted by the same code in every language. The data stays as it is: a
solution's ``branch.label`` and ``result.labels`` are English whatever the language, so
code that selects a branch by name works in every edition. Error messages are English too
(they are searched for, quoted in forums and matched by tests).

The language is read from the environment variable ``RIKIN_LANG`` (``en`` or ``es``; the
book's Spanish build sets it for its kernels, and the Spanish notebooks' first cell does
too) and can be set in a notebook with :func:`set_language`.

Examples
--------
>>> import rikin
>>> rikin.i18n.set_language("es")
>>> rikin.i18n.branch_name("front/up/no-flip")
'delante/arriba/sin voltear'
>>> rikin.i18n.set_language("en")
"""

from __future__ import annotations

import os

from .errors import InputError

__all__ = ["LANGUAGES", "language", "set_language"]

#: The languages rikin prints tables in.
LANGUAGES = ("en", "es")
#: The environment variable that chooses the language when :func:`set_language` was not called.
ENV_VAR = "RIKIN_LANG"

#: Spanish for the words tables print (the book's glossary gives the same terms).
_SPANISH = {
    # column headers
    "branch": "rama",
    "joint": "articulación",
    "type": "tipo",
    "offset": "desfase",
    "limits": "límites",
    # DH conventions
    "standard": "estándar",
    "modified": "modificado",
    # branch names: shoulder, elbow, wrist
    "front": "delante",
    "back": "detrás",
    "up": "arriba",
    "down": "abajo",
    "no-flip": "sin voltear",
    "flip": "volteada",
    "left": "izquierda",
    "right": "derecha",
    "towards": "hacia",
    "away": "opuesta",
    "singular": "singular",
    "unique": "única",
    # a solution named by its root ("root 2 of 4"): the numbers stay
    "root": "raíz",
    "of": "de",
    # cells
    "yes": "sí",
    "no": "no",
}
_WORDS = {"en": {}, "es": _SPANISH}

#: Spanish for the phrases figures print (str.format templates; the keys are the English).
_SPANISH_PHRASES = {
    "solution {n}": "solución {n}",
    "{name}: {k} IK solution": "{name}: {k} solución",
    "{name}: {k} IK solutions": "{name}: {k} soluciones",
    "joints where #{twins} has them": "mismos puntos articulares que #{twins}",
    "joints where #{twins} have them": "mismos puntos articulares que #{twins}",
    "all {k} solutions (legend: click to hide)": "las {k} soluciones (leyenda: clic para ocultar)",
    "all": "todas",
    "{name}: the target along a path": "{name}: el objetivo a lo largo de una trayectoria",
    "step {s}: unreachable: {why}": "paso {s}: inalcanzable: {why}",
    "step {s}: {n} solution": "paso {s}: {n} solución",
    "step {s}: {n} solutions": "paso {s}: {n} soluciones",
    "▶ play": "▶ reproducir",
    "path": "trayectoria",
    # drawings of one arm (rikin.plot)
    "{name} at q = {q}": "{name} en q = {q}",
    "{name}: DH frames ({convention}) at q = {q}":
        "{name}: sistemas DH ({convention}) en q = {q}",
    "{name}: wrist centre p_w = p − l·z (l = {l})":
        "{name}: centro de la muñeca p_w = p − l·z (l = {l})",
    "two-link triangle (law of cosines)": "triángulo de dos eslabones (teorema del coseno)",
    "TCP: {r_in} ≤ r ≤ {r_out}": "TCP: {r_in} ≤ r ≤ {r_out}",
    "wrist point: {w_in} ≤ r ≤ {w_out}": "centro de la muñeca: {w_in} ≤ r ≤ {w_out}",
    "{name}: reachable region": "{name}: región alcanzable",
    "{name}: {n} reachable TCP positions": "{name}: {n} posiciones alcanzables del TCP",
    "{name}: {n} reachable wrist centre positions":
        "{name}: {n} posiciones alcanzables del centro de la muñeca",
    "view from above": "vista desde arriba",
    "view along {axis}": "vista según {axis}",
    # the key under the all-solution figures (rikin.plot.MARKER_KEY)
    ("frame axes: x red, y green, z blue  ·  ○ revolute joint, □ prismatic joint  ·  "
     "★ TCP with the gripper (fingers open along y, approach along z)  ·  "
     "red ring: the target"):
    ("ejes de los sistemas: x rojo, y verde, z azul  ·  ○ articulación de rotación, "
     "□ articulación prismática  ·  ★ TCP con la pinza (dedos abiertos según y, "
     "aproximación según z)  ·  anillo rojo: el objetivo"),
    "approach along z": "aproximación según z",
    "approach along x": "aproximación según x",
    ", z blue": ", z azul",
    "light grey: the other solutions": "gris claro: las demás soluciones",
    "purple arrow: a joint axis reversed in the twin solution":
        "flecha morada: un eje articular invertido en la solución gemela",
    # an interactive figure whose script has not run (rikin.interactive)
    ("Interactive figure: run this cell to draw it (the notebook's own outputs are "
     "drawn; outputs saved in a file you did not run are not)."):
    ("Figura interactiva: ejecuta esta celda para dibujarla (se dibujan las salidas que "
     "el propio notebook genera; las guardadas en un archivo que no has ejecutado, no)."),
    ("This interactive figure needs plotly.js, which rikin puts in the first figure "
     "this page shows: it is drawn as soon as that one is; if it stays like this, "
     "run the notebook from its first cell again (Run All)."):
    ("Esta figura interactiva necesita plotly.js, que rikin pone en la primera figura de "
     "esta página: se dibuja en cuanto se dibuja aquella; si sigue así, vuelve a ejecutar "
     "el notebook desde su primera celda."),
    # a singular result's table (rikin.tables.solutions_table): rikin's reason, quoted
    "singular: {why}; free joints {free}": "singular: «{why}»; articulaciones libres {free}",
    # the DH panel's text (rikin.widgets.DHPanel): classify's verdict quoted as it says it
    "{verdict}": "«{verdict}»",
    # the teach panel's pose (rikin.widgets.Teach)
    "q = {q} → TCP at ({x}, {y}, {z}){units}, roll {roll}°, pitch {pitch}°, yaw {yaw}°":
        "q = {q} → TCP en ({x}, {y}, {z}){units}, roll {roll}°, pitch {pitch}°, yaw {yaw}°",
    # the DH panel's text (rikin.widgets.DHPanel)
    "DH table": "Tabla DH",
    "({convention} DH, {units}; tool at ({tool}); target joints ({target}))":
        "(DH {convention}, {units}; herramienta en ({tool}); articulaciones objetivo ({target}))",
    "({convention} DH, {units}; tool at ({tool}); target pose ({target}))":
        "(DH {convention}, {units}; herramienta en ({tool}); postura objetivo ({target}))",
    "no units": "sin unidades",
    "{n} solution, each put back through FK: largest pose error {err}":
        "{n} solución, comprobada con la cinemática directa: mayor error de postura {err}",
    "{n} solutions, each put back through FK: largest pose error {err}":
        "{n} soluciones, cada una comprobada con la cinemática directa: mayor error de "
        "postura {err}",
    "; the joints you typed are solution {k} ({label})":
        "; las articulaciones que escribiste son la solución {k} ({label})",
    ". Singular: {why}": ". Singular: «{why}»",
    "The table cannot be read: {why}": "No se puede leer la tabla: {why}",
    "the tool: {why}": "la herramienta: {why}",
    "The target cannot be read: {why}": "No se puede leer el objetivo: {why}",
    "Unreachable: {why}": "Inalcanzable: {why}",
    "No solution: {why}": "Sin solución: {why}",
    "classify:": "veredicto de classify:",
    "No closed form: {why}.": "Sin forma cerrada: «{why}».",
    " rikin.ik.ik_numerical cannot take this arm: {why}":
        " rikin.ik.ik_numerical no admite este brazo: {why}",
    "it found one solution": "ha encontrado una solución",
    "it did not converge ({why})": "no ha convergido ({why})",
    (" rikin.ik.ik_numerical (Levenberg-Marquardt from a seeded start): {how}; "
     "ik_numerical_multistart finds more, with no guarantee of all."):
    (" rikin.ik.ik_numerical (Levenberg-Marquardt desde un punto de partida con semilla "
     "fija): {how}; ik_numerical_multistart encuentra más, sin garantía de hallarlas todas."),
    (" rikin.ik.ik_numerical (Levenberg-Marquardt from a seeded start, for the TCP "
     "position): {how}; ik_numerical_multistart finds more, with no guarantee of all."):
    (" rikin.ik.ik_numerical (Levenberg-Marquardt desde un punto de partida con semilla "
     "fija, para la posición del TCP): {how}; ik_numerical_multistart encuentra más, sin "
     "garantía de hallarlas todas."),
    "{name}: ik_numerical's solution": "{name}: la solución de ik_numerical",
    "{name}: the arm at q = 0": "{name}: el brazo en q = 0",
    "every IK solution of the target, drawn":
        "todas las soluciones de la cinemática inversa del objetivo, dibujadas",
    # the DH panel's controls (rikin.widgets.DHPanel.widget): the values stay English
    "your arm": "tu brazo",
    "convention": "convención",
    "name": "nombre",
    "units": "unidades",
    "tool": "herramienta",
    "target as": "objetivo como",
    "joints": "articulaciones",
    "pose": "postura",
    "target": "objetivo",
    "x y z  or  x y z roll pitch yaw": "x y z  o  x y z roll pitch yaw",
    "q1 ... q6 (deg)  or  x y z roll pitch yaw": "q1 ... q6 (°)  o  x y z roll pitch yaw",
    "start from": "partir de",
    "(your table)": "(tu tabla)",
    "Epson C4 (modified DH)": "Epson C4 (DH modificado)",
    "UR5 (no spherical wrist)": "UR5 (sin muñeca esférica)",
    "Solve": "Resolver",
    ("<b>Your own arm</b>: one row per joint, <code>type d a alpha offset</code> (R or P; "
     "lengths in your units, angles in degrees or with pi: <code>-90</code>, "
     "<code>-90°</code>, <code>-pi/2</code>), or paste a table with a header row naming "
     "its columns in any order (<code>| joint | θ | d | a | α |</code>, joint variables "
     "such as <code>q2 + 90°</code>); press Solve for every IK solution of the target, "
     "drawn."):
    ("<b>Tu propio brazo</b>: una fila por articulación, <code>type d a alpha offset</code> "
     "(R o P; longitudes en tus unidades, ángulos en grados o con pi: <code>-90</code>, "
     "<code>-90°</code>, <code>-pi/2</code>), o pega una tabla con una fila de cabecera que "
     "nombre sus columnas en cualquier orden (<code>| joint | θ | d | a | α |</code>, "
     "variables articulares como <code>q2 + 90°</code>); pulsa Resolver y verás dibujadas "
     "todas las soluciones de la cinemática inversa del objetivo."),
    # the comments of the tables the DH panel offers (rikin.widgets.EXAMPLES)
    "KUKA KR5 (ARTE): m and degrees": "KUKA KR5 (ARTE): m y grados",
    "Epson C4, the lab's arm: mm and degrees":
        "Epson C4, el brazo del laboratorio: mm y grados",
    "Universal Robots UR5: m and degrees": "Universal Robots UR5: m y grados",
    "KUKA KR 5 arc: A1, A4, A6 counted against z (-q); limits as printed":
        "KUKA KR 5 arc: A1, A4 y A6 cuentan contra z (-q); límites como en la hoja de datos",
    "KUKA KR 5 arc (as KUKA counts A1-A6)": "KUKA KR 5 arc (A1-A6 como los cuenta KUKA)",
    "; {k} more outside the joint limits left out":
        "; {k} más, fuera de los límites articulares, descartadas",
    # the pose panel and the teach pendant (rikin.widgets.IKPanel, TeachPanel)
    "deg": "°",
    "target {values}": "objetivo {values}",
    "move the target; every IK solution is drawn with its branch":
        "mueve el objetivo: cada solución de la cinemática inversa se dibuja con su rama",
    "{n} solution": "{n} solución",
    "{n} solutions": "{n} soluciones",
    " (singular: {why})": " (singular: «{why}»)",
    "; {k} more outside the joint limits": "; {k} más fuera de los límites articulares",
    "no solution: {why}": "sin solución: {why}",
    "out of reach by {excess}": "fuera de alcance por {excess}",
    "out of reach": "fuera de alcance",
    "{name}: target out of reach\n(the arm at q = 0 for scale)":
        "{name}: objetivo fuera de alcance\n(el brazo en q = 0, como escala)",
    "{name} at the sliders' joint values":
        "{name} con los valores articulares de los deslizadores",
    # the legend of plot_two_link_triangle
    "elbow {branch}": "codo {branch}",
    # a panel's still picture (rikin.widgets.STILL_NOTE)
    ("A still picture of the live panel: this page cannot show widgets yet. After rikin's "
     "first install, reload the page (F5), then run the notebook again (Run All): "
     "JupyterLab and Jupyter Notebook load the widget support when a page opens."):
    ("Imagen fija del panel interactivo: esta página aún no puede mostrar widgets. Tras la "
     "primera instalación de rikin, recarga la página (F5) y vuelve a ejecutar el notebook "
     "(Run All): JupyterLab y Jupyter Notebook cargan el soporte de widgets al abrir una "
     "página."),
}
_PHRASES: dict[str, dict[str, str]] = {"en": {}, "es": _SPANISH_PHRASES}

_chosen: str | None = None


def _checked(lang: object, where: str) -> str:
    if not isinstance(lang, str) or lang.strip().lower() not in LANGUAGES:
        raise InputError(f"{where} must be one of {', '.join(LANGUAGES)}, got {lang!r}")
    return lang.strip().lower()


def set_language(language: str | None) -> None:
    """Print tables in ``language`` ("en" or "es") from now on; ``None`` goes back to
    ``RIKIN_LANG`` (English when it is not set)."""
    global _chosen
    _chosen = None if language is None else _checked(language, "language")


def language() -> str:
    """The language tables are printed in now: "en" or "es"."""
    if _chosen is not None:
        return _chosen
    value = os.environ.get(ENV_VAR, "").strip()
    return _checked(value, f"the environment variable {ENV_VAR}") if value else "en"


def word(text: str) -> str:
    """``text`` in the current language (unchanged when it has no translation)."""
    return _WORDS[language()].get(text, text)


def phrase(english: str, **values: object) -> str:
    """The phrase ``english`` (a :meth:`str.format` template) in the current language,
    filled in with ``values`` (formatted as in English: the numbers are the same)."""
    return _PHRASES[language()].get(english, english).format(**values)


def branch_name(label: str) -> str:
    """A branch label such as ``"front/up/no-flip"`` or ``"root 2 of 4/up"`` in the current
    language, word by word (the words of :data:`rikin.ik.result.LABEL_WORDS`; numbers stay)."""
    return "/".join(" ".join(word(w) for w in part.split(" ")) for part in label.split("/"))
