# Types the stubs (_plumb.pyi) cannot read from the module: its numpy arrays, lists and dicts
# are Python objects to nanobind, so nanobind's stub generator writes `object` or a bare `list`.
# Each entry is a regular expression for a name of plumb._plumb, then the lines that replace
# its stub (\doc: its docstring; \name: the group of that name). Patterns apply in order, the
# first that matches wins. python/tests/test_typing.py runs mypy --strict (python/requirements-
# typing.txt) over a script that touches every result type (python/tests/typed_user.py), so a
# wrong or missing type fails it.

plumb\._plumb\.__prefix__$:
    import numpy
    import numpy.typing
    import builtins
    from typing import Any
    _Floats = numpy.typing.NDArray[numpy.float64]
    _Pixels = numpy.typing.NDArray[numpy.uint8]
    __version__: str

# plumb's exceptions and warnings: made in the module, named plumb.X (so the generator would
# import them from plumb, which imports them from here): declared here instead
plumb\._plumb\.Error$:
    class Error(Exception):
        \doc

plumb\._plumb\.LoadError$:
    class LoadError(Error):
        \doc
        hint: str

plumb\._plumb\.(?P<name>PathError|MujocoError|UnavailableError|EngineError)$:
    class \name(Error):
        \doc

plumb\._plumb\.ValueError$:
    class ValueError(Error, builtins.ValueError):
        \doc

plumb\._plumb\.ArgumentError$:
    class ArgumentError(ValueError):
        \doc
        argument: str
        value: str
        problem: str

plumb\._plumb\.IoError$:
    class IoError(Error, OSError):
        \doc

plumb\._plumb\.EngineRefused$:
    class EngineRefused(EngineError):
        \doc

plumb\._plumb\.InternalError$:
    class InternalError(RuntimeError):
        \doc

plumb\._plumb\.RehearsalFailed$:
    class RehearsalFailed(Error):
        \doc
        result: RehearsalResult

plumb\._plumb\.PlumbWarning$:
    class PlumbWarning(UserWarning):
        \doc

plumb\._plumb\.(?P<name>CompileWarning|StartWarning|LogWarning|BatchWarning|ModelWarning)$:
    class \name(PlumbWarning):
        \doc


\.Model\.mjmodel$:
    @property
    def mjmodel(self) -> mujoco.MjModel | None:
        \doc

\.(VerifyResult|AuditResult|RehearsalResult)\.rows$:
    @property
    def rows(self) -> list[CheckRow]: ...

\.Description\.to_pandas$:
    def to_pandas(self, table: str = 'bodies') -> Any:
        \doc

\.to_pandas$:
    def to_pandas(self) -> Any:
        \doc

\.Trajectory\.to_dict$:
    def to_dict(self) -> list[dict[str, float]]:
        \doc

\.to_dict$:
    def to_dict(self) -> Any:
        \doc

\.save_report$:
    def save_report(self, path: str | os.PathLike[str]) -> None:
        \doc

\.(ReplayResult\.(?P<a>max_abs)|IdentifyResult\.(?P<b>nominal|lo|hi|singular_values))$:
    @property
    def \a\b(self) -> _Floats: ...

\.(ConvergeResult\.(?P<a>dt|values|errors)|Trajectory\.(?P<b>array|time)|Description\.(?P<c>gravity)|Frames\.(?P<d>times)|Batch\.(?P<e>params|metrics|diverged_at)|ReplayResult\.(?P<f>fits|fits_beyond_noise|rms|noise)|IdentifyResult\.(?P<g>values|std_errors|correlation|covariance|fits_before|fits_after))$:
    @property
    def \a\b\c\d\e\f\g(self) -> _Floats:
        \doc

\.DiffResult\.(?P<name>changes|compiler)$:
    @property
    def \name(self) -> list[dict[str, Any]]: ...

\.(VerifyResult\.(?P<a>horizon)|Batch\.(?P<b>summary)|RehearsalResult\.(?P<c>trace))$:
    @property
    def \a\b\c(self) -> dict[str, Any]:
        \doc

\.Description\.sizes$:
    @property
    def sizes(self) -> dict[str, int]: ...

\.Trajectory\.divergence$:
    @property
    def divergence(self) -> dict[str, Any] | None:
        \doc

\.Trajectory\.warnings$:
    @property
    def warnings(self) -> list[dict[str, Any]]:
        \doc

\.Trajectory\.__getitem__$:
    def __getitem__(self, column: str) -> _Floats:
        \doc

\.Description\.(?P<name>bodies|joints|actuators|sensors|delays|roles)$:
    @property
    def \name(self) -> list[dict[str, Any]]: ...

\.Description\.units$:
    @property
    def units(self) -> dict[str, str]: ...

\.Frames\.array$:
    @property
    def array(self) -> _Pixels: ...

\.Frames\.__getitem__$:
    def __getitem__(self, frame: int) -> _Pixels:
        \doc

\.Batch\.index$:
    @property
    def index(self) -> numpy.typing.NDArray[numpy.int64]:
        \doc

\.Batch\.diverged$:
    @property
    def diverged(self) -> numpy.typing.NDArray[numpy.bool_]:
        \doc

\.Batch\.problems$:
    @property
    def problems(self) -> list[str]:
        \doc

\.Batch\.column$:
    def column(self, name: str) -> numpy.typing.NDArray[Any]:
        \doc

\.ReplayResult\.(?P<name>simulated|times|logged)$:
    @property
    def \name(self) -> list[_Floats]:
        \doc

plumb\._plumb\.render$:
    def render(model: Model | mujoco.MjModel | str | os.PathLike[str], state: mujoco.MjData | Trajectory | None = None, *, camera: str | int = 'auto', width: int = 640, height: int = 480, set: Mapping[str, float | str | Sequence[float]] | Sequence[str] | str | None = None, keyframe: str | int | None = None, at: float = 0.0, until: float | None = None, fps: float = 30.0, highlight: str | Sequence[str] | None = None, msaa: bool = False, shadow_size: int = 0, gl: str = 'auto', output: str | os.PathLike[str] | None = None) -> _Pixels | Frames:
        \doc
