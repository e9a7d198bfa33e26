"""The robots sweep in the report: robots.html, one table over all robots, linked from every page's navigation."""

from harness.files import robots
from harness.report.site import build_site
from tests.test_robots_causes import ARM, TRIANGLE


def test_robots_page_has_the_table_and_is_linked(tmp_path):
    urdf = tmp_path / "arm.urdf"
    urdf.write_text(ARM.format(name="synthetic_arm", upper=TRIANGLE))
    record = robots.sweep_robot(("synthetic_arm", str(urdf), 3, 0))
    out = tmp_path / "reports"
    out.mkdir()
    robots.write(robots.document([record], 3, 0, 1.0, 1, "harness robots"), out)
    result = build_site(out, progress=open("/dev/null", "w"))
    assert "robots.html" in result["pages"]
    page = (out / "robots.html").read_text()
    assert "synthetic_arm" in page and "disagree-explained" in page and "balanceinertia" in page
    for header in ("robot", "DoF", "base", "worst (error / bound = ratio)", "findings", "time s"):
        assert f"<th>{header}</th>" in page
    assert 'href="robots.html"' in (out / "index.html").read_text()
