"""mtcal's own marker: the table ``mtcal_owner`` with one row naming the history's owner, so that a database is
known as mtcal's by mtcal's mark and not by Alembic's revision alone (another program's Alembic database may well
be at a revision called 0001).

Revision ID: 0002
Revises: 0001
Create Date: 2026-12-01
"""
import sqlalchemy as sa
from alembic import op

revision = "0002"
down_revision = "0001"
branch_labels = None
depends_on = None

OWNER = "mtcal calibration history"  # mtcal.history.store.OWNER (tests/test_history.py checks they agree)


def upgrade() -> None:
    owner = op.create_table("mtcal_owner", sa.Column("owner", sa.String(64), primary_key=True))
    op.bulk_insert(owner, [{"owner": OWNER}])


def downgrade() -> None:
    op.drop_table("mtcal_owner")
