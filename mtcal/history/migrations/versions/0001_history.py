"""The first schema of the history store: machines, their results (one row per added file) and the quantities
read from each result (one row per error and position).

Revision ID: 0001
Revises:
Create Date: 2026-11-27
"""
import sqlalchemy as sa
from alembic import op

revision = "0001"
down_revision = None
branch_labels = None
depends_on = None


def upgrade() -> None:
    op.create_table(
        "machines",
        sa.Column("id", sa.String(64), primary_key=True),
        sa.Column("spec", sa.String(64), nullable=True),
        sa.Column("created_at", sa.String(32), nullable=False),
    )
    op.create_table(
        "results",
        sa.Column("id", sa.Integer, primary_key=True, autoincrement=True),
        sa.Column("machine_id", sa.String(64), sa.ForeignKey("machines.id"), nullable=False),
        sa.Column("kind", sa.String(16), nullable=False),
        sa.Column("date", sa.Date, nullable=False),
        sa.Column("added_at", sa.String(32), nullable=False),
        sa.Column("spec", sa.String(64), nullable=True),
        sa.Column("source", sa.Text, nullable=False),
        sa.Column("file_sha256", sa.String(64), nullable=False),
        sa.Column("recording_sha256", sa.String(64), nullable=True),
        sa.Column("model_sha256", sa.String(64), nullable=True),
        sa.Column("tool_version", sa.String(32), nullable=False),
        sa.Column("instrument", sa.Text, nullable=True),
        sa.Column("environment", sa.Text, nullable=True),
        sa.Column("document", sa.Text, nullable=False),
        sa.UniqueConstraint("machine_id", "file_sha256", name="uq_results_machine_file"),
    )
    op.create_index("ix_results_machine_date", "results", ["machine_id", "date"])
    op.create_table(
        "quantities",
        sa.Column("id", sa.Integer, primary_key=True, autoincrement=True),
        sa.Column("result_id", sa.Integer, sa.ForeignKey("results.id", ondelete="CASCADE"), nullable=False),
        sa.Column("name", sa.String(32), nullable=False),
        sa.Column("axis", sa.String(16), nullable=True),
        sa.Column("position", sa.Float, nullable=True),
        sa.Column("value", sa.Float, nullable=False),
        sa.Column("u95", sa.Float, nullable=True),
        sa.Column("dof", sa.Float, nullable=True),
        sa.Column("unit", sa.String(16), nullable=False),
    )
    op.create_index("ix_quantities_result", "quantities", ["result_id"])


def downgrade() -> None:
    op.drop_index("ix_quantities_result", "quantities")
    op.drop_table("quantities")
    op.drop_index("ix_results_machine_date", "results")
    op.drop_table("results")
    op.drop_table("machines")
