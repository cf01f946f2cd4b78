"""The methods of the typed documents of the studies over replicates: `gmwm fit --joint` and
`gmwm select --joint` (docs/cli.md "JSON", docs/multi-signal.md). Their fields and from_dict
are generated from report/schema/results.json into _types.py."""
from __future__ import annotations

from typing import TYPE_CHECKING, Any, Mapping

from ._common import FloatArray, HasParameters, built, column_texts, g

if TYPE_CHECKING:
    from ._types import (BestFit, ContinuousParameter, GoodnessOfFit, JointFitColumn, JointSelectColumn, Kalman,
                         ReplicateFit, ReplicateOwnFit, ReplicateTest)


class ReplicateOwnFitMethods(HasParameters):
    model: str
    status: str

    def __repr__(self) -> str:
        return f"ReplicateOwnFit({self.model}, {self.status})"


class ReplicateFitMethods:
    source: str
    n: int
    fit: ReplicateOwnFit

    def __repr__(self) -> str:
        return f"ReplicateFit({self.source}: n={self.n}, {self.fit.status}, objective {g(self.fit.objective)})"


class AgmwmMethods:
    value: FloatArray

    def __repr__(self) -> str:
        return f"Agmwm({len(self.value)} parameters)"


class ReplicateBootstrapMethods:
    method: str
    draws: int

    def __repr__(self) -> str:
        return f"ReplicateBootstrap({self.method}, {self.draws} draws)"


class ReplicateTestMethods:
    p_value: float
    heterogeneity_p_value: float

    def __repr__(self) -> str:
        return f"ReplicateTest(p={g(self.p_value, 3)}, heterogeneity p={g(self.heterogeneity_p_value, 3)})"


class JointFitColumnMethods(HasParameters):
    name: str
    model_structure: str
    status: str
    gof: GoodnessOfFit
    replicates: tuple[ReplicateFit, ...]
    replicate_test: ReplicateTest | None

    def __repr__(self) -> str:
        shared = "" if self.replicate_test is None else f", shared-theta p={g(self.replicate_test.p_value, 3)}"
        return (f"JointFitColumn({self.name}: {self.model_structure} over {len(self.replicates)} recordings, "
                f"{self.status}, gof p={g(self.gof.p_value, 3)}{shared})")


def joint_fit_columns(d: Any, text: str) -> tuple[JointFitColumn, ...]:
    """The document's columns, each built from its own text."""
    from ._types import JointFitColumn

    return tuple(built(JointFitColumn, t) for t in column_texts(text))


class JointFitResultMethods:
    columns: tuple[JointFitColumn, ...]

    def __repr__(self) -> str:
        return "JointFitResult(" + "; ".join(f"{c.name}: {c.model_structure}, {c.status}" for c in self.columns) + ")"


class JointRankingRowMethods:
    rank: int
    model: str
    cv_wvic: float

    def __repr__(self) -> str:
        return f"JointRankingRow({self.rank}: {self.model}, cv_wvic {g(self.cv_wvic)})"


def training_of(d: Mapping[str, Any]) -> tuple[tuple[int, ...], ...]:
    """Each cross-validation split's training recordings (0-based indices)."""
    return tuple(tuple(int(i) for i in s) for s in d["training"])


def joint_best_fit(d: Mapping[str, Any]) -> BestFit | None:
    """The recommended model fitted jointly, as a BestFit of the column (None without one)."""
    from ._types import BestFit

    return BestFit.from_dict(d) if "best_fit" in d else None


class JointSelectColumnMethods:
    name: str
    chosen: str
    recommended: str
    replicates: tuple[str, ...]
    best_fit: BestFit | None

    @property
    def best_continuous(self) -> tuple[ContinuousParameter, ...]:
        """The recommended model's parameters in physical units (empty without a best fit)."""
        return self.best_fit.continuous if self.best_fit else ()

    @property
    def best_kalman(self) -> Kalman | None:
        """The recommended model's Kalman terms (None without a best fit)."""
        return self.best_fit.kalman if self.best_fit else None

    def __repr__(self) -> str:
        return (f"JointSelectColumn({self.name}: chosen {self.chosen}, recommended {self.recommended}, "
                f"{len(self.replicates)} recordings)")


def joint_select_columns(d: Any, text: str) -> tuple[JointSelectColumn, ...]:
    """The document's columns, each built from its own text."""
    from ._types import JointSelectColumn

    return tuple(built(JointSelectColumn, t) for t in column_texts(text))


class JointSelectResultMethods:
    columns: tuple[JointSelectColumn, ...]

    def __repr__(self) -> str:
        return "JointSelectResult(" + "; ".join(f"{c.name}: {c.recommended}" for c in self.columns) + ")"
